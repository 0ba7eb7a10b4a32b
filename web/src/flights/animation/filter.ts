// The playback filters (types.ts TrafficFilter) on the CPU: the same tests the GPU applies to the tails
// and the API applies to positions (edges included; an unknown altitude fails any band; west > east
// crosses 180°).

import { TSAN_NO_ICAO } from './tsan';
import type { TrafficFilter } from './types';

export interface CompiledFilter {
  active: boolean;
  altMin: number;
  altMax: number;
  hasAlt: boolean;
  /** Upper-case callsign pattern ('' = any). */
  callsign: string;
  /** ICAO 24-bit addresses as numbers (null = any). */
  icao24: Set<number> | null;
  /** A flight-level test (callsign or icao24) is set. */
  byFlight: boolean;
  bbox: [number, number, number, number] | null;
}

export function compileFilter(f: TrafficFilter): CompiledFilter {
  const hasAlt = f.altMinM !== undefined || f.altMaxM !== undefined;
  const callsign = (f.callsign ?? '').trim().toUpperCase();
  const icao24 = f.icao24 && f.icao24.length > 0 ? new Set(f.icao24.map((s) => parseInt(s, 16))) : null;
  const bbox = f.bbox ?? null;
  const byFlight = callsign !== '' || icao24 !== null;
  return {
    active: hasAlt || byFlight || bbox !== null,
    hasAlt,
    altMin: f.altMinM ?? -Infinity,
    altMax: f.altMaxM ?? Infinity,
    callsign,
    icao24,
    byFlight,
    bbox,
  };
}

/**
 * Whether `callsign` (upper-case) matches `pattern` by the API's rule: no wildcard = prefix; else a glob
 * where `*` matches any run and `?` one character, backtracking on the last `*` (compute/src/trails/query.cpp
 * callsign_matches, the same algorithm, so the two can never disagree).
 */
export function callsignMatches(pattern: string, callsign: string): boolean {
  if (!/[*?]/.test(pattern)) return callsign.startsWith(pattern);
  let p = 0;
  let c = 0;
  let star = -1;
  let mark = 0;
  while (c < callsign.length) {
    if (p < pattern.length && (pattern[p] === '?' || pattern[p] === callsign[c])) {
      p++;
      c++;
    } else if (p < pattern.length && pattern[p] === '*') {
      star = p++;
      mark = c;
    } else if (star >= 0) {
      p = star + 1;
      c = ++mark;
    } else {
      return false;
    }
  }
  while (p < pattern.length && pattern[p] === '*') p++;
  return p === pattern.length;
}

/** The flight-level tests: callsign pattern and icao24 list (an unknown address fails a list). */
export function flightPasses(c: CompiledFilter, callsign: string, icao24: number): boolean {
  if (c.icao24 && (icao24 === TSAN_NO_ICAO || !c.icao24.has(icao24))) return false;
  return c.callsign === '' || callsignMatches(c.callsign, callsign.toUpperCase());
}

export function inBBox(b: [number, number, number, number], lon: number, lat: number): boolean {
  const [w, s, e, n] = b;
  if (!(lat >= s && lat <= n)) return false;
  return w <= e ? lon >= w && lon <= e : lon >= w || lon <= e;
}

/** Whether a position passes the altitude band and bbox (the per-instant tests). */
export function positionPasses(c: CompiledFilter, lon: number, lat: number, altM: number): boolean {
  if (c.hasAlt && !(altM >= c.altMin && altM <= c.altMax)) return false;
  if (c.bbox && !inBBox(c.bbox, lon, lat)) return false;
  return true;
}
