// The playback filters (types.ts TrafficFilter) on the CPU: the same tests the GPU applies to the tails
// and the API applies to positions (edges included; an unknown altitude fails any band; west > east
// crosses 180°).

import type { TrafficFilter } from './types';

export interface CompiledFilter {
  active: boolean;
  altMin: number;
  altMax: number;
  hasAlt: boolean;
  prefix: string;
  bbox: [number, number, number, number] | null;
}

export function compileFilter(f: TrafficFilter): CompiledFilter {
  const hasAlt = f.altMinM !== undefined || f.altMaxM !== undefined;
  const prefix = (f.callsignPrefix ?? '').trim().toUpperCase();
  const bbox = f.bbox ?? null;
  return {
    active: hasAlt || prefix !== '' || bbox !== null,
    hasAlt,
    altMin: f.altMinM ?? -Infinity,
    altMax: f.altMaxM ?? Infinity,
    prefix,
    bbox,
  };
}

export const callsignPasses = (c: CompiledFilter, callsign: string) => c.prefix === '' || callsign.toUpperCase().startsWith(c.prefix);

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
