// Per-teat time series for the trajectory plots: estimated and true tip coordinates (mm) and the 3D error.

import { distance3, type Vec3 } from '../api/trackerLog';
import type { FrameStore } from './frameStore';

export interface TeatSeries {
  /** [axis][frame], NaN where the tracker has no track of the teat or the frame is unknown. */
  estimate: [Float64Array, Float64Array, Float64Array];
  /** [axis][frame], NaN without truth. */
  truth: [Float64Array, Float64Array, Float64Array];
  /** |estimate − truth| per frame where both exist and the truth says the teat is visible, else NaN. */
  error: Float64Array;
}

function triple(n: number): [Float64Array, Float64Array, Float64Array] {
  return [new Float64Array(n).fill(NaN), new Float64Array(n).fill(NaN), new Float64Array(n).fill(NaN)];
}

export function teatSeries(store: FrameStore, teat: number): TeatSeries {
  const n = store.frames;
  const out: TeatSeries = { estimate: triple(n), truth: triple(n), error: new Float64Array(n).fill(NaN) };
  for (let i = 0; i < n; i++) {
    const est = store.records[i]?.teats[teat];
    const tr = store.truth[i]?.teats[teat];
    let e: Vec3 | null = null;
    if (est && est.tracked && est.tipMm) {
      e = est.tipMm;
      for (let a = 0; a < 3; a++) out.estimate[a]![i] = e[a]!;
    }
    if (tr && tr.tipMm) {
      for (let a = 0; a < 3; a++) out.truth[a]![i] = tr.tipMm[a]!;
      if (e && tr.visible) out.error[i] = distance3(e, tr.tipMm);
    }
  }
  return out;
}

/** [min, max] over finite values of several arrays, padded by 5 %; [0, 1] when there are none. */
export function extent(arrays: ArrayLike<number>[]): [number, number] {
  let lo = Infinity;
  let hi = -Infinity;
  for (const a of arrays)
    for (let i = 0; i < a.length; i++) {
      const v = a[i]!;
      if (Number.isFinite(v)) {
        if (v < lo) lo = v;
        if (v > hi) hi = v;
      }
    }
  if (!Number.isFinite(lo)) return [0, 1];
  if (hi - lo < 1e-9) return [lo - 1, hi + 1];
  const pad = (hi - lo) * 0.05;
  return [lo - pad, hi + pad];
}
