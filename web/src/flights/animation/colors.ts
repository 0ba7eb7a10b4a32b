// Colours of the aircraft and their tails: numeric ramps (altitude, ground speed, vertical rate) and a
// categorical palette of callsign prefixes (the three-letter ICAO airline designator), with their legend.

import { ALTITUDE_STOPS_FT } from '../../lib/colors';
import type { ColorBy, Legend } from './types';

const FT = 0.3048;

export interface Ramp {
  unit: string;
  /** Value → colour stops, ascending values. */
  stops: ReadonlyArray<readonly [number, string]>;
}

/** The numeric ramps; altitude reuses the selected track's ramp (lib/colors.ts) in metres. */
export const RAMPS: Record<Exclude<ColorBy, 'callsign'>, Ramp> = {
  altitude: { unit: 'm', stops: ALTITUDE_STOPS_FT.map(([ft, c]) => [Math.round(ft * FT), c] as const) },
  speed: {
    unit: 'm/s',
    stops: [[0, '#3b4cc0'], [75, '#22d3ee'], [150, '#3ddc84'], [225, '#facc15'], [300, '#f43f5e']],
  },
  vrate: {
    unit: 'm/s',
    stops: [[-15, '#38bdf8'], [-3, '#7dd3fc'], [0, '#e5e7eb'], [3, '#fdba74'], [15, '#f97316']],
  },
};

/** Categorical colours of callsign prefixes (Tableau 10 + 2, readable on the dark basemap). */
export const PALETTE = [
  '#4e79a7', '#f28e2b', '#e15759', '#76b7b2', '#59a14f', '#edc948',
  '#b07aa1', '#ff9da7', '#9c755f', '#bab0ac', '#8cd17d', '#d4a6c8',
] as const;
/** Colour of an aircraft whose value is unknown (NaN) or without callsign. */
export const UNKNOWN_COLOR = '#9ca3af';

/** The prefix a callsign is grouped by: its first three characters, upper-case ('' without callsign). */
export const callsignPrefix = (cs: string) => cs.trim().slice(0, 3).toUpperCase();

/** Palette index of a prefix (a stable string hash), or -1 for ''. */
export function prefixCategory(prefix: string): number {
  if (prefix === '') return -1;
  let h = 2166136261;
  for (let i = 0; i < prefix.length; i++) h = Math.imul(h ^ prefix.charCodeAt(i), 16777619);
  return (h >>> 0) % PALETTE.length;
}

export function hexToRgb(hex: string): [number, number, number] {
  const v = parseInt(hex.slice(1), 16);
  return [(v >> 16) & 255, (v >> 8) & 255, v & 255];
}

/** A 256-texel RGBA ramp over [stops[0], stops[last]] (linear between stops), for the GPU. */
export function rampTexels(r: Ramp): Uint8Array {
  const out = new Uint8Array(256 * 4);
  const lo = r.stops[0]![0], hi = r.stops[r.stops.length - 1]![0];
  for (let i = 0; i < 256; i++) {
    const v = lo + ((hi - lo) * i) / 255;
    let k = 0;
    while (k < r.stops.length - 2 && v > r.stops[k + 1]![0]) k++;
    const [v0, c0] = r.stops[k]!, [v1, c1] = r.stops[k + 1]!;
    const w = Math.min(1, Math.max(0, (v - v0) / (v1 - v0)));
    const a = hexToRgb(c0), b = hexToRgb(c1);
    for (let j = 0; j < 3; j++) out[4 * i + j] = Math.round(a[j]! + (b[j]! - a[j]!) * w);
    out[4 * i + 3] = 255;
  }
  return out;
}

/** The palette as 256 texels (each colour repeated over 256/PALETTE.length texels). */
export function paletteTexels(): Uint8Array {
  const out = new Uint8Array(256 * 4);
  for (let i = 0; i < 256; i++) {
    const c = hexToRgb(PALETTE[Math.min(PALETTE.length - 1, Math.floor((i * PALETTE.length) / 256))]!);
    out.set([c[0], c[1], c[2], 255], 4 * i);
  }
  return out;
}

/**
 * The legend: a numeric ramp's stops with their values, or the callsign prefixes of the aircraft drawn
 * now (the `prefixes` counts), most frequent first, at most 12.
 */
export function legendOf(c: ColorBy, prefixes?: Map<string, number>): Legend {
  if (c !== 'callsign') return { colorBy: c, unit: RAMPS[c].unit, stops: RAMPS[c].stops.map(([value, color]) => ({ value, color })) };
  const top = [...(prefixes ?? new Map<string, number>()).entries()]
    .filter(([p]) => p !== '')
    .sort((a, b) => b[1] - a[1] || (a[0] < b[0] ? -1 : 1))
    .slice(0, PALETTE.length);
  return { colorBy: c, unit: '', stops: top.map(([p]) => ({ value: p, color: PALETTE[prefixCategory(p)]! })) };
}
