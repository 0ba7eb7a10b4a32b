// Selection rules of the runs dashboard: table clicks (plain, toggle, shift range) and which selected runs
// the comparison shows (2..8 runs of one video).

import type { RunRow } from '../api/runsTypes';
import { metricDef, metricValue } from './metrics';

export const MAX_COMPARE = 8;

/** The ids between the anchor and the target (inclusive) in `order`; just the target without an anchor. */
export function rangeIds(order: readonly string[], anchor: string | null, target: string): string[] {
  const b = order.indexOf(target);
  if (b < 0) return [];
  const a = anchor === null ? -1 : order.indexOf(anchor);
  if (a < 0) return [target];
  const [lo, hi] = a <= b ? [a, b] : [b, a];
  return order.slice(lo, hi + 1);
}

/** A table click on `id`: plain = only it, toggle (ctrl/cmd, checkbox) = add or remove, range (shift) = add the range. */
export function clickSelect(
  selected: readonly string[],
  order: readonly string[],
  anchor: string | null,
  id: string,
  mode: 'replace' | 'toggle' | 'range',
): string[] {
  if (mode === 'replace') return [id];
  if (mode === 'toggle') return selected.includes(id) ? selected.filter((s) => s !== id) : [...selected, id];
  const add = rangeIds(order, anchor, id);
  const set = new Set(selected);
  return [...selected, ...add.filter((s) => !set.has(s))];
}

export interface ComparePick {
  video: string | null;
  /** The runs compared (2..8, one video), best first by `metric`; empty when fewer than 2. */
  ids: string[];
  /** Selected runs of that video. */
  ofVideo: number;
  /** Selected runs in all. */
  selected: number;
}

/**
 * The runs the comparison shows for a selection: those of the video most selected runs are on (ties: the
 * first selected run's video); when more than 8, 8 spread evenly over their range of `metric` (the best,
 * the worst and six between), so a brushed region shows its spread of outcomes. Ordered best first.
 */
export function pickCompare(selected: readonly string[], rows: ReadonlyMap<string, RunRow>, metric: string): ComparePick {
  const byVideo = new Map<string, string[]>();
  for (const id of selected) {
    const r = rows.get(id);
    if (!r) continue;
    const l = byVideo.get(r.video) ?? [];
    l.push(id);
    byVideo.set(r.video, l);
  }
  let video: string | null = null;
  let ids: string[] = [];
  for (const [v, l] of byVideo) if (l.length > ids.length) [video, ids] = [v, l];
  const ofVideo = ids.length;
  const def = metricDef(metric);
  const key = (id: string) => {
    const v = metricValue(rows.get(id)!, def.key);
    return Number.isNaN(v) ? -Infinity : def.better === 'high' ? v : -v;
  };
  const sorted = [...ids].sort((a, b) => key(b) - key(a) || a.localeCompare(b, 'en', { numeric: true }));
  let pick = sorted;
  if (sorted.length > MAX_COMPARE) {
    const idx = new Set<number>();
    for (let k = 0; k < MAX_COMPARE; k++) idx.add(Math.round((k * (sorted.length - 1)) / (MAX_COMPARE - 1)));
    pick = [...idx].sort((a, b) => a - b).map((i) => sorted[i]!);
  }
  return { video, ids: pick.length >= 2 ? pick : [], ofVideo, selected: selected.length };
}
