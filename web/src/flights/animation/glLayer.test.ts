import { describe, expect, it } from 'vitest';
import { buildSegments, metresMatrix } from './glLayer';
import { decodeTsan } from './tsan';
import { encodeTsan, rng, type TestFlight } from './tsanTestEncoder';
import { legendOf, prefixCategory, rampTexels, RAMPS, PALETTE } from './colors';

const DAY = 1514764800;

describe('tail segments of a chunk', () => {
  const r = rng(7);
  const fl: TestFlight[] = [...Array(40).keys()].map((id) => {
    let t = DAY + 1000 + r() * 400;
    return {
      id, icao24: '', callsign: `X${id}`,
      samples: [...Array(30).keys()].map(() => ({ t: (t += 3 + Math.floor(r() * 40)), lon: 10 + r(), lat: 50 + r(), alt: r() * 1e4, speed: 200, track: 0, vrate: 0 })),
    };
  });
  const d = 300, t0 = DAY + 1200;
  const c = decodeTsan(encodeTsan(fl, t0, d, [10, 50]));
  const s = buildSegments(c);

  it('holds every segment that overlaps the chunk, once, bucketed by clipped start second', () => {
    // Brute force: consecutive samples of one flight whose [ta, tb] overlaps [0, d).
    let expected = 0;
    for (let f = 0; f < c.nFlights; f++)
      for (let a = c.first[f]!; a < c.first[f]! + c.count[f]! - 1; a++) if (c.t[a + 1]! > 0 && c.t[a]! < d && c.t[a + 1]! > c.t[a]!) expected++;
    expect(s.segments).toBe(expected);
    expect(s.bucketStart[s.bucketStart.length - 1]).toBe(expected);
    let maxDur = 0;
    for (let k = 0; k < s.segments; k++) {
      const ta = s.data[12 * k]!, tb = s.data[12 * k + 1]!;
      const b = Math.min(s.bucketStart.length - 2, Math.floor(Math.max(ta, 0)));
      expect(k).toBeGreaterThanOrEqual(s.bucketStart[b]!);
      expect(k).toBeLessThan(s.bucketStart[b + 1]!);
      maxDur = Math.max(maxDur, Math.min(tb, d) - Math.max(ta, 0));
      // The segment's ends are samples of the flight it names.
      const f = s.data[12 * k + 9]!;
      const a = [...Array(c.count[f]!).keys()].map((i) => c.first[f]! + i).find((i) => c.t[i] === ta)!;
      expect(c.t[a + 1]).toBe(tb);
      expect(s.data[12 * k + 2]).toBe(c.x[a]);
      expect(s.data[12 * k + 5]).toBe(c.y[a + 1]);
    }
    expect(s.maxDur).toBe(maxDur);
  });
});

describe('metres → clip matrix', () => {
  it('equals MapLibre unit Mercator coordinates through its matrix', () => {
    // An arbitrary affine "map matrix" (column-major) of unit Mercator coordinates.
    const M = [3000, 0, 0, 0, 0, -2000, 0, 0, 0, 0, 1, 0, -1580.3, 1040.7, 0, 1];
    const R = 6378137;
    const ox = R * (10 * Math.PI) / 180, oy = R * Math.asinh(Math.tan((50 * Math.PI) / 180));
    const m = metresMatrix(M, ox, oy);
    for (const [lon, lat] of [[10, 50], [12.5, 47.25], [-3, 58]] as const) {
      const X = R * (lon * Math.PI) / 180, Y = R * Math.asinh(Math.tan((lat * Math.PI) / 180));
      const ux = (lon + 180) / 360, uy = 0.5 - Math.asinh(Math.tan((lat * Math.PI) / 180)) / (2 * Math.PI);
      const x = X - ox, y = Y - oy;
      expect(m[0]! * x + m[4]! * y + m[12]!).toBeCloseTo(M[0]! * ux + M[4]! * uy + M[12]!, 9);
      expect(m[1]! * x + m[5]! * y + m[13]!).toBeCloseTo(M[1]! * ux + M[5]! * uy + M[13]!, 9);
    }
  });
});

describe('colours and legend', () => {
  it('ramps run through their stops', () => {
    const px = rampTexels(RAMPS.altitude);
    expect([...px.slice(0, 3)]).toEqual([0x3d, 0xdc, 0x84]); // the first stop
    expect([...px.slice(255 * 4, 255 * 4 + 3)]).toEqual([0xf4, 0x72, 0xb6]); // the last
    expect(legendOf('speed')).toMatchObject({ unit: 'm/s', stops: [{ value: 0 }, { value: 75 }, { value: 150 }, { value: 225 }, { value: 300 }] });
  });

  it('callsign legend: most frequent prefixes first, each with its palette colour', () => {
    const l = legendOf('callsign', new Map([['DLH', 5], ['BAW', 9], ['', 20], ['AFR', 5]]));
    expect(l.stops.map((s) => s.value)).toEqual(['BAW', 'AFR', 'DLH']);
    expect(l.stops[0]!.color).toBe(PALETTE[prefixCategory('BAW')]);
    expect(prefixCategory('')).toBe(-1);
  });
});
