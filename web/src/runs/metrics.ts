// The run-summary figures the dashboard shows, how to read them from a run row, how to format them, and
// which direction is better. The figures themselves are defined by the server's run summary: the accuracy
// figures (accuracy.*) by compute/src/tracker/accuracy.cpp, the summary that holds them with track_share,
// lost_episodes and tracker_fps by server/src/store/run_store.cpp. This list only gives them labels, units
// and the better direction (metricDef falls back to the key itself for a figure not listed here).

import type { RunRow } from '../api/runsTypes';

export interface MetricDef {
  /** Dotted path in the run summary (as GET /api/v1/importance and the projection columns name it). */
  key: string;
  label: string;
  short: string;
  unit: '' | '%' | 'mm' | 'fps';
  better: 'high' | 'low';
}

export const METRICS: readonly MetricDef[] = [
  { key: 'track_share', label: 'Track share', short: 'track', unit: '%', better: 'high' },
  { key: 'accuracy.frames_all_within', label: 'Frames all within', short: 'within', unit: '%', better: 'high' },
  { key: 'accuracy.median_error_mm', label: 'Median error', short: 'med err', unit: 'mm', better: 'low' },
  { key: 'accuracy.p95_error_mm', label: 'P95 error', short: 'p95 err', unit: 'mm', better: 'low' },
  { key: 'lost_episodes', label: 'Lost episodes', short: 'lost', unit: '', better: 'low' },
  { key: 'tracker_fps', label: 'Tracker speed', short: 'speed', unit: 'fps', better: 'high' },
];

export function metricDef(key: string): MetricDef {
  const k = key.replace(/^metric:/, '');
  return METRICS.find((m) => m.key === k) ?? { key: k, label: k, short: k, unit: k.endsWith('_mm') ? 'mm' : '', better: 'high' };
}

/** The figure at a dotted path of the run's summary; NaN when missing or null. */
export function metricValue(row: RunRow, key: string): number {
  let v: unknown = row.summary;
  for (const part of key.replace(/^metric:/, '').split('.')) {
    if (!v || typeof v !== 'object') return NaN;
    v = (v as Record<string, unknown>)[part];
  }
  return typeof v === 'number' && Number.isFinite(v) ? v : NaN;
}

export function paramValue(row: RunRow, name: string): number {
  const i = row.param_names.indexOf(name.replace(/^param:/, ''));
  const v = i >= 0 ? row.params[i] : undefined;
  return typeof v === 'number' && Number.isFinite(v) ? v : NaN;
}

/** Parameters not constant over the rows, in the first row's order. */
export function varyingParams(rows: readonly RunRow[]): string[] {
  if (rows.length === 0) return [];
  const names = rows[0]!.param_names;
  return names.filter((n) => {
    let first: number | undefined;
    for (const r of rows) {
      const v = paramValue(r, n);
      if (Number.isNaN(v)) continue;
      if (first === undefined) first = v;
      else if (Math.abs(v - first) > 1e-12 * Math.max(1, Math.abs(first))) return true;
    }
    return false;
  });
}

function trim(v: number, digits: number): string {
  return v.toFixed(digits).replace(/\.?0+$/, '') || '0';
}

/** A number with about three significant digits ("0.352", "17.4", "4000"). */
export function formatNumber(v: number): string {
  if (Number.isNaN(v)) return '–';
  if (!Number.isFinite(v)) return v > 0 ? '∞' : '−∞';
  const a = Math.abs(v);
  if (a === 0) return '0';
  if (a >= 1000) return Math.round(v).toLocaleString('en-US');
  if (a >= 100) return trim(v, 0);
  if (a >= 10) return trim(v, 1);
  if (a >= 1) return trim(v, 2);
  return trim(v, 3);
}

export function formatMetric(key: string, v: number): string {
  if (Number.isNaN(v)) return '–';
  const d = metricDef(key);
  switch (d.unit) {
    case '%':
      return `${(v * 100).toFixed(v >= 0.9995 || v === 0 ? 0 : 1)} %`;
    case 'mm':
      return `${formatNumber(v)} mm`;
    case 'fps':
      return `${Math.round(v)} fps`;
    default:
      return formatNumber(v);
  }
}

/** A parameter value with its unit ("22 mm", "0.35"). */
export function formatParam(v: number, unit = ''): string {
  const s = formatNumber(v);
  return unit && s !== '–' ? `${s} ${unit}` : s;
}

/** Index of the best finite value (by `better`), or -1. Ties: the first. */
export function bestIndex(values: readonly number[], better: 'high' | 'low'): number {
  let best = -1;
  for (let i = 0; i < values.length; i++) {
    const v = values[i]!;
    if (Number.isNaN(v)) continue;
    if (best < 0 || (better === 'high' ? v > values[best]! : v < values[best]!)) best = i;
  }
  return best;
}
