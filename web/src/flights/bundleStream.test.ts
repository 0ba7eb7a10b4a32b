import { afterEach, beforeEach, describe, expect, it, vi } from 'vitest';
import { ClockThrottle, decodeTsbs, frameToGeoJson, TsbsError } from './bundleStream';

// A TSBS frame written field by field from proto/bundle_stream.md (an encoder independent of the decoder).
function encode(t: number, seq: number, windowS: number, drift: number, trails: { id: number; o: number; pts: [number, number][] }[]): ArrayBuffer {
  const n = trails.length;
  const m = trails.reduce((s, tr) => s + tr.pts.length, 0);
  const buf = new ArrayBuffer(44 + 12 * n + 8 * m);
  const dv = new DataView(buf);
  'TSBS'.split('').forEach((c, i) => dv.setUint8(i, c.charCodeAt(0)));
  dv.setUint32(4, 1, true);
  dv.setUint32(8, n, true);
  dv.setUint32(12, m, true);
  dv.setFloat64(16, t, true);
  dv.setUint32(24, seq, true);
  dv.setFloat32(28, windowS, true);
  dv.setFloat32(32, drift, true);
  dv.setUint32(36, 0, true);
  let at = 40;
  for (const tr of trails) dv.setUint32(at, tr.id, true), (at += 4);
  for (const tr of trails) dv.setFloat32(at, tr.o, true), (at += 4);
  let off = 0;
  dv.setUint32(at, 0, true), (at += 4);
  for (const tr of trails) (off += tr.pts.length), dv.setUint32(at, off, true), (at += 4);
  for (const tr of trails) for (const [x, y] of tr.pts) dv.setFloat32(at, x, true), dv.setFloat32(at + 4, y, true), (at += 8);
  return buf;
}

describe('decodeTsbs', () => {
  const trails = [
    { id: 7, o: 0.25, pts: [[2.5, 48.75], [3.5, 49.25], [4.5, 50.5]] as [number, number][] },
    { id: 4000000000, o: 1, pts: [[-0.5, 51.5], [181.25, 52]] as [number, number][] },
  ];
  it('reads every field at its documented offset', () => {
    // A late time of day: float64 keeps the second (a float32 epoch would be off by up to 64 s).
    const f = decodeTsbs(encode(1514847599, 42, 3600, 0.75, trails));
    expect(f.t).toBe(1514847599);
    expect(f.sequence).toBe(42);
    expect(f.windowS).toBe(3600);
    expect(f.driftPx).toBe(0.75);
    expect(f.n).toBe(2);
    expect(f.m).toBe(5);
    expect(Array.from(f.ids)).toEqual([7, 4000000000]);
    expect(Array.from(f.opacity)).toEqual([0.25, 1]);
    expect(Array.from(f.offsets)).toEqual([0, 3, 5]);
    expect(Array.from(f.points)).toEqual([2.5, 48.75, 3.5, 49.25, 4.5, 50.5, -0.5, 51.5, 181.25, 52]);
  });
  it('decodes an empty window', () => {
    const f = decodeTsbs(encode(1e9, 1, 60, 0, []));
    expect(f.n).toBe(0);
    expect(Array.from(f.offsets)).toEqual([0]);
    expect(frameToGeoJson(f).features).toEqual([]);
  });
  it('turns trails into lines with their id and opacity', () => {
    const g = frameToGeoJson(decodeTsbs(encode(1e9, 1, 60, 0, trails)));
    expect(g.features).toHaveLength(2);
    expect(g.features[0].properties).toEqual({ id: 7, o: 0.25 });
    expect(g.features[1].geometry.coordinates).toEqual([[-0.5, 51.5], [181.25, 52]]);
  });
  it('rejects malformed frames with the reason', () => {
    const good = encode(1e9, 1, 60, 0, trails);
    expect(() => decodeTsbs(good.slice(0, 20))).toThrow(new TsbsError('20 bytes is shorter than the header'));
    const magic = good.slice(0);
    new DataView(magic).setUint8(3, 0x4c);
    expect(() => decodeTsbs(magic)).toThrow('TSBS: bad magic "TSBL"');
    const version = good.slice(0);
    new DataView(version).setUint32(4, 2, true);
    expect(() => decodeTsbs(version)).toThrow('TSBS: version 2 is not 1');
    expect(() => decodeTsbs(good.slice(0, good.byteLength - 8))).toThrow('100 bytes, expected 108 for 2 trails and 5 points');
    const offsets = good.slice(0);
    new DataView(offsets).setUint32(40 + 8 * 2 + 4, 6, true); // offsets[1] = 6 > offsets[2] = 5
    expect(() => decodeTsbs(offsets)).toThrow('TSBS: offsets decrease at trail 1');
  });
});

describe('ClockThrottle', () => {
  beforeEach(() => vi.useFakeTimers());
  afterEach(() => vi.useRealTimers());
  it('sends the first clock at once and coalesces the rest of an interval into the newest', () => {
    let now = 0;
    const sent: number[] = [];
    const th = new ClockThrottle(100, (t) => sent.push(t), () => now);
    th.push(10);
    expect(sent).toEqual([10]);
    now = 30, th.push(11);
    now = 60, th.push(12);
    expect(sent).toEqual([10]);
    now = 100, vi.advanceTimersByTime(70);
    expect(sent).toEqual([10, 12]);
    now = 250, th.push(13);
    expect(sent).toEqual([10, 12, 13]);
    now = 260, th.push(14);
    th.cancel();
    vi.advanceTimersByTime(500);
    expect(sent).toEqual([10, 12, 13]);
  });
});
