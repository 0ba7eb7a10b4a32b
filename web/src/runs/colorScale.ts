// Sequential colour scale of the projection and the parallel coordinates: viridis over the finite values
// of a metric (reversed when lower is better, so that bright is always good), grey for NaN.

import { COLORMAP_STOPS } from '../lib/colors';

export const NAN_COLOR = '#56606d';

export interface ColorScale {
  lo: number;
  hi: number;
  reversed: boolean;
  /** CSS colour of a value; NAN_COLOR for NaN, clamped to the ends outside [lo, hi]. */
  color(v: number): string;
  /** Position 0..1 of a value on the ramp (before reversal), NaN for NaN. */
  t(v: number): number;
  /** The ramp's stops from lo to hi (for the legend). */
  stops: readonly string[];
}

function hexToRgb(hex: string): [number, number, number] {
  const n = parseInt(hex.slice(1), 16);
  return [(n >> 16) & 255, (n >> 8) & 255, n & 255];
}

/** Linear interpolation between evenly spaced stops at t in [0, 1]. */
export function rampColor(stops: readonly string[], t: number): string {
  const x = Math.min(1, Math.max(0, t)) * (stops.length - 1);
  const i = Math.min(stops.length - 2, Math.floor(x));
  const f = x - i;
  const a = hexToRgb(stops[i]!);
  const b = hexToRgb(stops[i + 1]!);
  const c = a.map((v, k) => Math.round(v + (b[k]! - v) * f));
  return `rgb(${c[0]}, ${c[1]}, ${c[2]})`;
}

export function colorScale(values: ArrayLike<number>, opts: { reversed?: boolean; stops?: readonly string[] } = {}): ColorScale {
  let lo = Infinity;
  let hi = -Infinity;
  for (let i = 0; i < values.length; i++) {
    const v = values[i]!;
    if (!Number.isFinite(v)) continue;
    if (v < lo) lo = v;
    if (v > hi) hi = v;
  }
  if (!Number.isFinite(lo)) {
    lo = 0;
    hi = 1;
  }
  const reversed = opts.reversed ?? false;
  const base = opts.stops ?? COLORMAP_STOPS.viridis;
  const stops = reversed ? [...base].reverse() : base;
  const t = (v: number) => (Number.isNaN(v) ? NaN : hi > lo ? Math.min(1, Math.max(0, (v - lo) / (hi - lo))) : 0.5);
  return {
    lo,
    hi,
    reversed,
    stops,
    t,
    color: (v: number) => (Number.isNaN(v) ? NAN_COLOR : rampColor(stops, t(v))),
  };
}
