import { describe, expect, it } from 'vitest';
import { EMPTY_FILTERS } from '../../api/query';
import { congestionBody, congestionTileTemplate, type RequestInput } from './request';

const base: RequestInput = {
  dataset: { id: 'europe', t_min: 1514764800.5, t_max: 1514851199.75 },
  filters: { ...EMPTY_FILTERS },
  mapBBox: [-10.123456, 35.5, 30.000049, 60.25],
  sectors: null,
  compute: ['occupancy', 'hotspots'],
  method: 'interpolated',
  fields: {},
};

describe('congestionBody', () => {
  it('without a window: the data set range, half-open; the grid over the map view', () => {
    expect(congestionBody(base)).toEqual({
      dataset: 'europe',
      query: { t0: 1514764800, t1: 1514851200 },
      volumes: { grid: { bbox: [-10.1235, 35.5, 30, 60.25] } },
      compute: ['occupancy', 'hotspots'],
      method: 'interpolated',
    });
  });
  it('the window, callsign, icao24 and the altitude band in feet; the form', () => {
    const b = congestionBody({
      ...base,
      filters: { ...EMPTY_FILTERS, t0: 1514800000, t1: 1514803600, callsign: 'AFR*', icao24: 'abc123', altMin: 20000, altMax: 40000, onGround: 'false' },
      mapBBox: null,
      fields: { step: '30', duration: ' 120 ', peak: '6', sustained: '', sustained_steps: '4' },
      method: 'samples',
    });
    expect(b).toEqual({
      dataset: 'europe',
      query: { t0: 1514800000, t1: 1514803600, callsign: 'AFR*', icao24: 'abc123' },
      volumes: { grid: { alt_min: 20000, alt_max: 40000, alt_unit: 'ft' } },
      compute: ['occupancy', 'hotspots'],
      method: 'samples',
      step: 30,
      duration: 120,
      thresholds: { peak: 6, sustained_steps: 4 },
    });
  });
  it('a sector set replaces the grid (no bbox, no band); text that is no number is sent as typed', () => {
    const b = congestionBody({ ...base, sectors: 's3', filters: { ...EMPTY_FILTERS, altMin: 100 }, fields: { peak: 'ten' } });
    expect(b.volumes).toEqual({ sectors: 's3' });
    expect(b.thresholds).toEqual({ peak: 'ten' });
  });
});

describe('congestionTileTemplate', () => {
  it('an instant, or the window, with the filters and the threshold', () => {
    const f = { ...EMPTY_FILTERS, t0: 100, t1: 200, callsign: 'AFR*', altMin: 20000 };
    expect(congestionTileTemplate('http://h', 'eu rope', f, 1514849999.5, 2)).toBe(
      'http://h/api/v1/datasets/eu%20rope/congestion/tiles/{z}/{x}/{y}.png?t=1514849999.5&alt_min=20000&alt_unit=ft&callsign=AFR*&threshold=2',
    );
    expect(congestionTileTemplate('', 'e', f, null, 1)).toBe('/api/v1/datasets/e/congestion/tiles/{z}/{x}/{y}.png?t0=100&t1=200&alt_min=20000&alt_unit=ft&callsign=AFR*&threshold=1');
  });
});
