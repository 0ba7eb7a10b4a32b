import { describe, expect, it } from 'vitest';
import { decodeTsan, icaoText, TsanError } from './tsan';
import { encodeTsan, rng, type TestFlight, type TestSample } from './tsanTestEncoder';
import { frameAt } from './frame';
import { compileFilter } from './filter';

const f32 = Math.fround;
const DAY = 1514764800; // 2018-01-01T00:00:00Z

function sample(t: number, lon: number, lat: number, alt = 10000, extra: Partial<TestSample> = {}): TestSample {
  return { t, lon: f32(lon), lat: f32(lat), alt: f32(alt), speed: f32(230), track: f32(90), vrate: f32(0), ...extra };
}

/** Random flights over Europe sampled every 5-60 s over a day, the store's float32 lon/lat. */
function flights(seed: number, count: number): TestFlight[] {
  const r = rng(seed);
  const out: TestFlight[] = [];
  for (let id = 0; id < count; id++) {
    const start = DAY + r() * 80000;
    const n = 5 + Math.floor(r() * 200);
    let t = start, lon = -10 + r() * 40, lat = 35 + r() * 25, alt = r() * 12000;
    const s: TestSample[] = [];
    for (let k = 0; k < n; k++) {
      s.push(sample(t, lon, lat, alt, { speed: f32(100 + r() * 150), track: f32(r() * 360), vrate: f32(r() * 20 - 10), onGround: alt < 50 }));
      t += 5 + Math.floor(r() * 56);
      lon += (r() - 0.5) * 0.4;
      lat += (r() - 0.5) * 0.3;
      alt = Math.max(0, alt + (r() - 0.5) * 600);
    }
    out.push({ id: id * 3 + 1, icao24: r() < 0.1 ? '' : Math.floor(r() * 0xffffff).toString(16).padStart(6, '0'), callsign: r() < 0.05 ? '' : `AB${id}Ø`, samples: s });
  }
  return out;
}

/**
 * The API's positions_at() rule, written again over the flights' own samples (not the chunk): presence
 * t_min <= t <= t_max, exact sample as is, else latitude and altitude linear, longitude the short way.
 */
function reference(fl: TestFlight[], t: number) {
  const out: Array<{ id: number; lon: number; lat: number; alt: number }> = [];
  for (const f of fl) {
    const s = f.samples;
    if (!(s[0]!.t <= t && t <= s[s.length - 1]!.t)) continue;
    let i = 0;
    while (s[i]!.t < t) i++;
    if (s[i]!.t === t) {
      out.push({ id: f.id, lon: s[i]!.lon, lat: s[i]!.lat, alt: s[i]!.alt });
      continue;
    }
    const a = s[i - 1]!, b = s[i]!;
    const w = (t - a.t) / (b.t - a.t);
    let d = b.lon - a.lon;
    if (Math.abs(d) > 180) d += d > 0 ? -360 : 360;
    let lon = a.lon + d * w;
    if (lon >= 180) lon -= 360;
    if (lon < -180) lon += 360;
    out.push({ id: f.id, lon, lat: a.lat + (b.lat - a.lat) * w, alt: a.alt + (b.alt - a.alt) * w });
  }
  return out;
}

/** Ground distance in metres (equirectangular, exact enough below a kilometre). */
function metres(lon1: number, lat1: number, lon2: number, lat2: number) {
  let dl = lon2 - lon1;
  if (dl > 180) dl -= 360;
  if (dl < -180) dl += 360;
  const k = (6371008.8 * Math.PI) / 180;
  return Math.hypot(dl * k * Math.cos(((lat1 + lat2) / 2) * (Math.PI / 180)), (lat2 - lat1) * k);
}

describe('TSAN decoding', () => {
  it('decodes header, flight table, columns and callsigns as encoded', () => {
    const fl: TestFlight[] = [
      { id: 7, icao24: '4ca7b5', callsign: 'EIN12', samples: [sample(DAY + 100, 1, 50), sample(DAY + 200, 2, 51, 9000, { onGround: true }), sample(DAY + 400, 3, 52)] },
      { id: 9, icao24: '', callsign: '', samples: [sample(DAY + 249, 0, 40)] },
    ];
    const c = decodeTsan(encodeTsan(fl, DAY + 150, 100, [0, 45]));
    expect(c.tStart).toBe(DAY + 150);
    expect(c.duration).toBe(100);
    expect(c.nFlights).toBe(2);
    // Flight 7: the sample before (100), the one inside (200) and the first at or after the end (400).
    expect([...c.flightId]).toEqual([7, 9]);
    expect([...c.first]).toEqual([0, 3]);
    expect([...c.count]).toEqual([3, 1]);
    expect([...c.t]).toEqual([-50, 50, 250, 99]);
    expect(c.callsign).toEqual(['EIN12', '']);
    expect(icaoText(c.icao24[0]!)).toBe('4ca7b5');
    expect(icaoText(c.icao24[1]!)).toBe('');
    expect([...c.onGround]).toEqual([0, 1, 0, 0]);
    expect(c.alt[1]).toBe(9000);
    // x relative to the origin: 1° of longitude is R·π/180 metres.
    expect(c.x[1]! - c.x[0]!).toBeCloseTo((6378137 * Math.PI) / 180, 0);
  });

  it('refuses malformed buffers with a reason', () => {
    const good = encodeTsan(flights(3, 60), DAY + 36000, 3600, [10, 45]);
    expect(() => decodeTsan(good.slice(0, 40))).toThrow(/shorter than the header/);
    expect(() => decodeTsan(good.slice(0, good.byteLength - 8))).toThrow(/bytes, expected/);
    const bad = good.slice(0);
    new DataView(bad).setUint8(0, 0x58);
    expect(() => decodeTsan(bad)).toThrow(TsanError);
    const v2 = good.slice(0);
    new DataView(v2).setUint16(4, 2, true);
    expect(() => decodeTsan(v2)).toThrow(/version 2/);
    const overlap = good.slice(0);
    const n = new DataView(overlap).getUint32(40, true);
    if (n >= 2) {
      new DataView(overlap).setUint32(64 + 24 + 4, 0, true); // the second flight's samples start at 0
      expect(() => decodeTsan(overlap)).toThrow(/overlap/);
    }
  });
});

describe('positions drawn = the API rule, to the metre', () => {
  const fl = flights(42, 300);
  const origin: [number, number] = [10, 47];
  // Instants over the day, the late ones included (float32 epoch seconds would be 128 s apart there).
  const instants = [DAY + 3600.25, DAY + 43210.5, DAY + 80000, DAY + 86399.75, DAY + 86399.999];
  for (const d of [60, 300, 3600]) {
    it(`chunks of ${d} s`, () => {
      for (const t of instants) {
        const t0 = Math.floor(t / d) * d;
        const c = decodeTsan(encodeTsan(fl, t0, d, origin));
        const fr = frameAt(c, t, compileFilter({}));
        const ref = reference(fl, t);
        expect(fr.n).toBe(ref.length);
        let worst = 0;
        for (let i = 0; i < fr.n; i++) {
          const r = ref[i]!;
          expect(c.flightId[fr.flight[i]!]).toBe(r.id);
          worst = Math.max(worst, metres(fr.lon[i]!, fr.lat[i]!, r.lon, r.lat));
          expect(Math.abs(fr.alt[i]! - r.alt)).toBeLessThan(0.01);
        }
        expect(worst).toBeLessThan(1);
      }
    });
  }

  it('instants on samples give the sample; the antimeridian is crossed the short way', () => {
    const cross: TestFlight = { id: 1, icao24: 'abcdef', callsign: 'X', samples: [sample(DAY + 1000, 179.5, 10), sample(DAY + 1100, -179.5, 11)] };
    const c = decodeTsan(encodeTsan([cross], DAY + 900, 300, [0, 0]));
    const mid = frameAt(c, DAY + 1050, compileFilter({}));
    expect(mid.n).toBe(1);
    expect(Math.abs(Math.abs(mid.lon[0]!) - 180)).toBeLessThan(1e-6);
    expect(mid.lat[0]).toBeCloseTo(10.5, 6);
    const q = frameAt(c, DAY + 1025, compileFilter({}));
    expect(metres(q.lon[0]!, q.lat[0]!, 179.75, 10.25)).toBeLessThan(1);
    const atSample = frameAt(c, DAY + 1100, compileFilter({}));
    expect(atSample.n).toBe(1);
    expect(metres(atSample.lon[0]!, atSample.lat[0]!, -179.5, 11)).toBeLessThan(1);
    expect(frameAt(c, DAY + 1100.001, compileFilter({})).n).toBe(0);
    expect(frameAt(c, DAY + 999.999, compileFilter({})).n).toBe(0);
  });

  it('filters apply to the interpolated position (band edges included, bbox across 180°)', () => {
    const t = DAY + 43210.5;
    const c = decodeTsan(encodeTsan(fl, Math.floor(t / 300) * 300, 300, origin));
    const ref = reference(fl, t);
    const band = frameAt(c, t, compileFilter({ altMinM: 3000, altMaxM: 8000 }));
    expect(band.n).toBe(ref.filter((r) => r.alt >= 3000 && r.alt <= 8000).length);
    const box = frameAt(c, t, compileFilter({ bbox: [0, 40, 15, 55] }));
    expect(box.n).toBe(ref.filter((r) => r.lon >= 0 && r.lon <= 15 && r.lat >= 40 && r.lat <= 55).length);
    const wrap = frameAt(c, t, compileFilter({ bbox: [15, 30, 0, 70] })); // everything but 0..15°E
    expect(wrap.n).toBe(ref.filter((r) => r.lon >= 15 || r.lon <= 0).length);
    const pre = frameAt(c, t, compileFilter({ callsign: 'ab1' }));
    expect(pre.n).toBe(ref.filter((r) => fl.find((f) => f.id === r.id)!.callsign.startsWith('AB1')).length);
    expect(pre.n).toBeGreaterThan(0);
  });
});
