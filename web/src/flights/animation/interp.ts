// Where a flight of a TSAN chunk is at an instant, on the CPU in float64: the rule of the API's
// positions_at() (compute/include/trailscope/trails/positions.hpp) applied to a chunk's samples, so what
// the layer draws matches GET /api/v1/datasets/{id}/positions?t= to the metre:
//   - a sample at exactly t is used as is;
//   - otherwise, between the bracketing samples a and b with w = (t - ta) / (tb - ta): x (longitude)
//     linearly, the short way round across 180°; LATITUDE linearly (y of both samples back to latitude,
//     interpolated, projected again), not y: Mercator y is not linear in latitude;
//   - altitude, speed and vertical rate linearly (NaN when either end is unknown); track by the
//     shortest arc in [0, 360).
// Times: sample time = tStart + t_rel in float64, so no float32 epoch time is ever formed.

import type { TsanChunk } from './tsan';

/** Radius (metres) of the sphere of EPSG:3857 (compute/include/trailscope/geo/web_mercator.hpp). */
export const EARTH_RADIUS_M = 6378137.0;
/** Width of the Web Mercator world in metres. */
export const WORLD_M = 2 * Math.PI * EARTH_RADIUS_M;
const DEG = Math.PI / 180;

export const lonToMercX = (lon: number) => EARTH_RADIUS_M * lon * DEG;
export const latToMercY = (lat: number) => EARTH_RADIUS_M * Math.asinh(Math.tan(lat * DEG));
export const mercXToLon = (x: number) => x / (EARTH_RADIUS_M * DEG);
export const mercYToLat = (y: number) => Math.atan(Math.sinh(y / EARTH_RADIUS_M)) / DEG;

/** A flight's state at an instant. Unknown numbers are NaN. */
export interface FlightState {
  lon: number;
  lat: number;
  /** EPSG:3857 metres relative to the chunk's origin (float64; x unwrapped near the first sample's x). */
  x: number;
  y: number;
  altM: number;
  speedMs: number;
  trackDeg: number;
  vrateMs: number;
  onGround: boolean;
  exact: boolean;
}

/**
 * Index of the sample a of flight `f` with t_a <= t < t_b (tRel = t - tStart), or the last sample when
 * t equals it; -1 when the flight is absent at t. `hint` (a previous answer) makes playback O(1).
 */
export function bracket(c: TsanChunk, f: number, tRel: number, hint = -1): number {
  const lo0 = c.first[f]!, n = c.count[f]!, hi0 = lo0 + n - 1;
  const ts = c.t;
  if (tRel < ts[lo0]! || tRel > ts[hi0]!) return -1;
  if (tRel === ts[hi0]!) return hi0;
  if (hint >= lo0 && hint < hi0 && ts[hint]! <= tRel && tRel < ts[hint + 1]!) return hint;
  if (hint >= lo0 && hint + 1 < hi0 && ts[hint + 1]! <= tRel && tRel < ts[hint + 2]!) return hint + 1;
  let lo = lo0, hi = hi0; // ts[lo] <= tRel < ts[hi]
  while (hi - lo > 1) {
    const mid = (lo + hi) >>> 1;
    if (ts[mid]! <= tRel) lo = mid;
    else hi = mid;
  }
  return lo;
}

const lerp = (a: number, b: number, w: number) => (a !== a || b !== b ? NaN : a + (b - a) * w);

function lerpTrack(a: number, b: number, w: number): number {
  if (a !== a || b !== b) return NaN;
  let d = (b - a) % 360;
  if (d > 180) d -= 360;
  else if (d <= -180) d += 360;
  let tr = (a + d * w) % 360;
  if (tr < 0) tr += 360;
  if (tr >= 360) tr = 0;
  return tr;
}

/** Wraps a longitude into [-180, 180). */
export function wrapLon(lon: number): number {
  if (lon >= -180 && lon < 180) return lon;
  let w = (lon + 180) % 360;
  if (w < 0) w += 360;
  w -= 180;
  return w >= 180 ? -180 : w;
}

/**
 * The state of flight `f` (index in the chunk) at float64 Unix time `t` from sample `a` = bracket(...)
 * (>= 0). Writes into `out` and returns it.
 */
export function stateAt(c: TsanChunk, a: number, t: number, out: FlightState): FlightState {
  const ta = c.tStart + c.t[a]!;
  const ox = c.originX, oy = c.originY;
  if (ta === t || a + 1 >= c.nSamples) {
    out.x = c.x[a]!;
    out.y = c.y[a]!;
    out.lon = wrapLon(mercXToLon(ox + out.x));
    out.lat = mercYToLat(oy + out.y);
    out.altM = c.alt[a]!;
    out.speedMs = c.speed[a]!;
    out.trackDeg = c.track[a]!;
    out.vrateMs = c.vrate[a]!;
    out.onGround = c.onGround[a] !== 0;
    out.exact = ta === t;
    return out;
  }
  const b = a + 1;
  const tb = c.tStart + c.t[b]!;
  const w = (t - ta) / (tb - ta);
  const xa = c.x[a]!;
  let dx = c.x[b]! - xa;
  // The short way round: more than half the world apart means the flight crosses 180°.
  if (Math.abs(dx) > WORLD_M / 2) dx += dx > 0 ? -WORLD_M : WORLD_M;
  out.x = xa + dx * w;
  out.lon = wrapLon(mercXToLon(ox + out.x));
  const latA = mercYToLat(oy + c.y[a]!), latB = mercYToLat(oy + c.y[b]!);
  out.lat = latA + (latB - latA) * w;
  out.y = latToMercY(out.lat) - oy;
  out.altM = lerp(c.alt[a]!, c.alt[b]!, w);
  out.speedMs = lerp(c.speed[a]!, c.speed[b]!, w);
  out.trackDeg = lerpTrack(c.track[a]!, c.track[b]!, w);
  out.vrateMs = lerp(c.vrate[a]!, c.vrate[b]!, w);
  out.onGround = c.onGround[a] !== 0;
  out.exact = false;
  return out;
}

export function emptyState(): FlightState {
  return { lon: 0, lat: 0, x: 0, y: 0, altM: NaN, speedMs: NaN, trackDeg: NaN, vrateMs: NaN, onGround: false, exact: false };
}
