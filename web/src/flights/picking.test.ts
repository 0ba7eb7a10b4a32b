import { describe, expect, it } from 'vitest';
import { PICK_TOLERANCE_PX, pickQuery } from './picking';
import { DensityLegend } from './densityLegend';

describe('pickQuery', () => {
  it("keeps the tiles' filters and adds the point, MapLibre's zoom with 512-px tiles, the tolerance and the limit", () => {
    const q = pickQuery(new URLSearchParams('t0=100&t1=200&callsign=AFR'), 8.5706, 50.0333, 7.25, 3);
    expect(q.get('t0')).toBe('100');
    expect(q.get('callsign')).toBe('AFR');
    expect(q.get('lon')).toBe('8.570600');
    expect(q.get('lat')).toBe('50.033300');
    expect(q.get('zoom')).toBe('7.2500');
    expect(q.get('tile_size')).toBe('512');
    expect(q.get('tolerance')).toBe(String(PICK_TOLERANCE_PX));
    expect(q.get('limit')).toBe('3');
  });
});

describe('DensityLegend.tileZoom', () => {
  it('is the zoom of the 256-px tiles MapLibre requests: its zoom + 1, rounded, within the source zooms', () => {
    expect(DensityLegend.tileZoom(4.49)).toBe(5);
    expect(DensityLegend.tileZoom(4.5)).toBe(6);
    expect(DensityLegend.tileZoom(-0.9)).toBe(0);
    expect(DensityLegend.tileZoom(16.2)).toBe(14);
  });
});
