// Scales of the parallel coordinates: one vertical axis per varying parameter and metric, each spanning
// its own finite range; NaN sits in a "missing" band under the axis. Axis brushes are value intervals.

export interface PcAxis {
  key: string;
  label: string;
  lo: number;
  hi: number;
}

/** [lo, hi] over finite values; a constant column widens to ±0.5 (±|v|/2) so that it sits mid-axis. */
export function axisDomain(values: ArrayLike<number>): [number, number] {
  let lo = Infinity;
  let hi = -Infinity;
  for (let i = 0; i < values.length; i++) {
    const v = values[i]!;
    if (!Number.isFinite(v)) continue;
    lo = Math.min(lo, v);
    hi = Math.max(hi, v);
  }
  if (!Number.isFinite(lo)) return [0, 1];
  if (hi - lo < 1e-12) {
    const d = Math.abs(lo) > 0 ? Math.abs(lo) / 2 : 0.5;
    return [lo - d, hi + d];
  }
  return [lo, hi];
}

/** y (px) of a value on an axis from `top` (hi) to `bottom` (lo); NaN → `missing`. */
export function yOf(v: number, axis: { lo: number; hi: number }, top: number, bottom: number, missing = bottom + 14): number {
  if (!Number.isFinite(v)) return missing;
  const t = (v - axis.lo) / (axis.hi - axis.lo || 1);
  return bottom - Math.min(1, Math.max(0, t)) * (bottom - top);
}

/** The value at y (px), inverse of yOf inside the axis. */
export function valueAt(y: number, axis: { lo: number; hi: number }, top: number, bottom: number): number {
  const t = (bottom - Math.min(bottom, Math.max(top, y))) / (bottom - top || 1);
  return axis.lo + t * (axis.hi - axis.lo);
}

/** x (px) of axis i of n across a plot of `width` with `pad` px on both sides. */
export function axisX(i: number, n: number, width: number, pad: number): number {
  if (n <= 1) return width / 2;
  return pad + (i * (width - 2 * pad)) / (n - 1);
}

/** Whether a row (values by axis key) passes every brush (inclusive intervals; NaN never passes). */
export function passesBrushes(values: ReadonlyMap<string, number>, brushes: ReadonlyMap<string, [number, number]>): boolean {
  for (const [key, [a, b]] of brushes) {
    const v = values.get(key);
    if (v === undefined || !(v >= Math.min(a, b) && v <= Math.max(a, b))) return false;
  }
  return true;
}
