import { describe, expect, it } from 'vitest';
import { TsblError, blend, blendAt, blendSource, decodeTsbl, planeToLonLat, toPlane } from './tsbl';

/** Builds a TSBL buffer as the server writes it (proto/bundle_polylines.md). */
function encode(opts: {
  lonlat?: boolean;
  relaxation?: number;
  maxDisplacement?: number;
  lines: { bundled: [number, number][]; original: [number, number][]; length: number }[];
}): ArrayBuffer {
  const n = opts.lines.length;
  const m = opts.lines.reduce((s, l) => s + l.bundled.length, 0);
  const buf = new ArrayBuffer(36 + 8 * n + 16 * m);
  const dv = new DataView(buf);
  'TSBL'.split('').forEach((c, i) => dv.setUint8(i, c.charCodeAt(0)));
  dv.setUint32(4, 1, true);
  dv.setUint32(8, opts.lonlat ? 1 : 0, true);
  dv.setUint32(12, n, true);
  dv.setUint32(16, m, true);
  dv.setFloat32(20, opts.relaxation ?? 0, true);
  dv.setFloat32(24, opts.maxDisplacement ?? 0.2, true);
  let off = 32;
  let o = 0;
  dv.setUint32(off, 0, true);
  for (const l of opts.lines) {
    o += l.bundled.length;
    off += 4;
    dv.setUint32(off, o, true);
  }
  off += 4;
  for (const key of ['bundled', 'original'] as const)
    for (const l of opts.lines)
      for (const [x, y] of l[key]) {
        dv.setFloat32(off, x, true);
        dv.setFloat32(off + 4, y, true);
        off += 8;
      }
  for (const l of opts.lines) {
    dv.setFloat32(off, l.length, true);
    off += 4;
  }
  expect(off).toBe(buf.byteLength);
  return buf;
}

const twoLines = {
  maxDisplacement: 0.5,
  lines: [
    // A 10-long edge whose middle point was pulled up by 2.
    { bundled: [[0, 0], [5, 2], [10, 0]] as [number, number][], original: [[0, 0], [5, 0], [10, 0]] as [number, number][], length: 10 },
    // A 2-long edge pulled by 4: the cap (0.5 · 2 = 1) holds it back.
    { bundled: [[0, 10], [1, 14], [2, 10]] as [number, number][], original: [[0, 10], [1, 10], [2, 10]] as [number, number][], length: 2 },
  ],
};

describe('decodeTsbl', () => {
  it('reads the header and the sections', () => {
    const t = decodeTsbl(encode({ ...twoLines, relaxation: 0.25 }));
    expect(t.n).toBe(2);
    expect(t.m).toBe(6);
    expect(t.lonlat).toBe(false);
    expect(t.relaxation).toBe(0.25);
    expect(t.maxDisplacement).toBe(0.5);
    expect([...t.offsets]).toEqual([0, 3, 6]);
    expect([...t.bundled.slice(2, 4)]).toEqual([5, 2]);
    expect([...t.original.slice(2, 4)]).toEqual([5, 0]);
    expect([...t.length]).toEqual([10, 2]);
  });

  it('reads the lon/lat flag', () => {
    expect(decodeTsbl(encode({ ...twoLines, lonlat: true })).lonlat).toBe(true);
  });

  it('refuses a wrong magic, version or size', () => {
    const good = encode(twoLines);
    const bad = good.slice(0);
    new DataView(bad).setUint8(0, 'X'.charCodeAt(0));
    expect(() => decodeTsbl(bad)).toThrow(TsblError);
    expect(() => decodeTsbl(bad)).toThrow('bad magic "XSBL"');
    const v2 = good.slice(0);
    new DataView(v2).setUint32(4, 2, true);
    expect(() => decodeTsbl(v2)).toThrow('version 2 is not supported');
    expect(() => decodeTsbl(good.slice(0, good.byteLength - 4))).toThrow('TSBL: 144 bytes, expected 148 for 2 polylines of 6 points');
    expect(() => decodeTsbl(new ArrayBuffer(8))).toThrow('shorter than the header');
  });

  it('refuses offsets that do not cover the points', () => {
    const buf = encode(twoLines);
    new DataView(buf).setUint32(36, 7, true);
    expect(() => decodeTsbl(buf)).toThrow('offsets decrease');
  });
});

describe('blend', () => {
  const t = decodeTsbl(encode(twoLines));

  it('gives the bundled lines at 0 and the originals at 1', () => {
    const at0 = blend(t.bundled, t.original, t.offsets, t.length, t.maxDisplacement, 0);
    const at1 = blend(t.bundled, t.original, t.offsets, t.length, t.maxDisplacement, 1);
    expect([...at0.slice(0, 6)]).toEqual([0, 0, 5, 2, 10, 0]);
    expect([...at1]).toEqual([...t.original]);
  });

  it('interpolates linearly, l·p + (1 − l)·P', () => {
    const half = blend(t.bundled, t.original, t.offsets, t.length, t.maxDisplacement, 0.5);
    expect(half[3]).toBeCloseTo(1, 6);
    expect(half[2]).toBeCloseTo(5, 6);
  });

  it('caps the displacement at maxDisplacement · length', () => {
    const at0 = blend(t.bundled, t.original, t.offsets, t.length, t.maxDisplacement, 0);
    // Second line, middle point: |p − P| = 4 > cap 1, so l = 1/4 and the point sits 1 above its original.
    expect(at0[9]).toBeCloseTo(11, 6);
    expect(at0[8]).toBeCloseTo(1, 6);
    // lengthScale stretches the cap: 2 · 0.5 · 2 = 2 above.
    const scaled = blend(t.bundled, t.original, t.offsets, t.length, t.maxDisplacement, 0, 2);
    expect(scaled[9]).toBeCloseTo(12, 6);
  });

  it('clamps the relaxation to 0..1 and writes into a given buffer', () => {
    const out = new Float64Array(12);
    const r = blend(t.bundled, t.original, t.offsets, t.length, t.maxDisplacement, 7, 1, out);
    expect(r).toBe(out);
    expect([...out]).toEqual([...t.original]);
  });
});

describe('lon/lat plane', () => {
  it('projects to Web Mercator world units and back', () => {
    const p = toPlane(new Float32Array([0, 0, 8.5706, 50.0333, -180, 85.0511287798]), true);
    expect(p[0]).toBeCloseTo(0.5, 12);
    expect(p[1]).toBeCloseTo(0.5, 12);
    expect(p[5]).toBeCloseTo(0, 6);
    const [lon, lat] = planeToLonLat(p[2]!, p[3]!);
    expect(lon).toBeCloseTo(8.5706, 4);
    expect(lat).toBeCloseTo(50.0333, 4);
  });

  it('blends lon/lat data in the Mercator plane with lengths in Mercator degrees', () => {
    // The bundled end moved 1° east of the original; the cap (0.2 · 1 Mercator degree) limits the move to 0.2° east.
    const buf = encode({
      lonlat: true,
      maxDisplacement: 0.2,
      lines: [{ bundled: [[0, 0], [2, 0]], original: [[0, 0], [1, 0]], length: 1 }],
    });
    const s = blendSource(decodeTsbl(buf));
    const out = blendAt(s, 0);
    const [lon] = planeToLonLat(out[2]!, out[3]!);
    expect(lon).toBeCloseTo(1.2, 5);
    const [lonHalf] = planeToLonLat(blendAt(s, 0.9)[2]!, 0.5);
    expect(lonHalf).toBeCloseTo(1.1, 5);
  });
});
