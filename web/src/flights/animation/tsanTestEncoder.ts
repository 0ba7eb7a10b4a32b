// A TSAN encoder for the unit tests, written from proto/animation_chunks.md independently of the
// decoder: which flights and samples a chunk holds, and the byte layout. Not used by the app.

export interface TestSample {
  t: number; // Unix seconds (float64)
  lon: number;
  lat: number;
  alt: number;
  speed: number;
  track: number;
  vrate: number;
  onGround?: boolean;
}

export interface TestFlight {
  id: number;
  icao24: string; // hex or ''
  callsign: string;
  samples: TestSample[]; // time-sorted
}

const R = 6378137.0;
const mx = (lon: number) => (R * lon * Math.PI) / 180;
const my = (lat: number) => R * Math.log(Math.tan(Math.PI / 4 + (lat * Math.PI) / 360));

/** The samples of one flight a chunk [t0, t0 + d) holds, or null when the flight is not in it. */
export function chunkSamples(f: TestFlight, t0: number, d: number): TestSample[] | null {
  const s = f.samples;
  if (s.length === 0 || !(s[0]!.t < t0 + d && s[s.length - 1]!.t >= t0)) return null;
  const out: TestSample[] = [];
  let before: TestSample | null = null, after: TestSample | null = null;
  for (const p of s) {
    if (p.t < t0) before = p;
    else if (p.t < t0 + d) out.push(p);
    else if (!after) after = p;
  }
  if (before) out.unshift(before);
  if (after) out.push(after);
  return out;
}

/** Encodes the chunk [t0, t0 + d) of `flights` with origin (lon, lat) as TSAN version 1. */
export function encodeTsan(flights: TestFlight[], t0: number, d: number, origin: [number, number]): ArrayBuffer {
  const enc = new TextEncoder();
  const rows: Array<{ f: TestFlight; s: TestSample[]; cs: Uint8Array }> = [];
  for (const f of [...flights].sort((a, b) => a.id - b.id)) {
    const s = chunkSamples(f, t0, d);
    if (s) rows.push({ f, s, cs: enc.encode(f.callsign) });
  }
  const n = rows.reduce((a, r) => a + r.s.length, 0);
  const strBytes = rows.reduce((a, r) => a + r.cs.length, 0);
  const p8 = (v: number) => Math.ceil(v / 8) * 8;
  const size = 64 + p8(24 * rows.length) + 7 * p8(4 * n) + p8(n) + p8(strBytes);
  const buf = new ArrayBuffer(size);
  const dv = new DataView(buf);
  'TSAN'.split('').forEach((c, i) => dv.setUint8(i, c.charCodeAt(0)));
  dv.setUint16(4, 1, true);
  dv.setUint16(6, 0, true);
  dv.setFloat64(8, t0, true);
  dv.setFloat64(16, d, true);
  const ox = mx(origin[0]), oy = my(origin[1]);
  dv.setFloat64(24, ox, true);
  dv.setFloat64(32, oy, true);
  dv.setUint32(40, rows.length, true);
  dv.setUint32(44, n, true);
  dv.setUint32(48, strBytes, true);
  let rec = 64, k = 0, so = 0;
  const cols = 64 + p8(24 * rows.length);
  const colAt = (c: number) => cols + c * p8(4 * n);
  const ogAt = colAt(7);
  const strAt = ogAt + p8(n);
  for (const r of rows) {
    dv.setUint32(rec, r.f.id, true);
    dv.setUint32(rec + 4, k, true);
    dv.setUint32(rec + 8, r.s.length, true);
    dv.setUint32(rec + 12, r.f.icao24 ? parseInt(r.f.icao24, 16) : 0xffffffff, true);
    dv.setUint32(rec + 16, so, true);
    dv.setUint32(rec + 20, r.cs.length, true);
    new Uint8Array(buf, strAt + so, r.cs.length).set(r.cs);
    so += r.cs.length;
    rec += 24;
    for (const p of r.s) {
      const vals = [p.t - t0, mx(p.lon) - ox, my(p.lat) - oy, p.alt, p.speed, p.track, p.vrate];
      vals.forEach((v, c) => dv.setFloat32(colAt(c) + 4 * k, v, true));
      dv.setUint8(ogAt + k, p.onGround ? 1 : 0);
      k++;
    }
  }
  return buf;
}

/** mulberry32: a small seeded generator for repeatable test data. */
export function rng(seed: number): () => number {
  return () => {
    seed |= 0;
    seed = (seed + 0x6d2b79f5) | 0;
    let t = Math.imul(seed ^ (seed >>> 15), 1 | seed);
    t = (t + Math.imul(t ^ (t >>> 7), 61 | t)) ^ t;
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
}
