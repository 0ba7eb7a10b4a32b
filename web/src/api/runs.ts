// The runs API (stored runs, sweeps, importance, projections, comparisons) and the parsing of a
// comparison into typed arrays for drawing.

import { request } from './client';
import type {
  CompareRequest,
  CompareRun,
  CompareSeries,
  Comparison,
  Disagreement,
  Importance,
  Projection,
  ProjectionRequest,
  RunRow,
  Sweep,
  SweepSpecBody,
  ValueRow,
} from './runsTypes';
import type { TrackerState } from './trackerLog';
import type { Job } from './types';


function post<T>(path: string, body: unknown, signal?: AbortSignal): Promise<T> {
  return request<T>(path, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body), signal });
}

const enc = encodeURIComponent;

export const runsApi = {
  runs: async (signal?: AbortSignal) => (await request<{ runs: RunRow[] }>('/api/v1/runs', { signal })).runs ?? [],
  sweeps: async (signal?: AbortSignal) => (await request<{ sweeps: Sweep[] }>('/api/v1/sweeps', { signal })).sweeps ?? [],
  sweep: (id: string, signal?: AbortSignal) => request<Sweep>(`/api/v1/sweeps/${enc(id)}`, { signal }),
  startSweep: (videos: string[], sweep: SweepSpecBody) => post<{ job: Job; sweep: Sweep }>('/api/v1/sweeps', { videos, sweep }),
  job: (id: string, signal?: AbortSignal) => request<Job>(`/api/v1/jobs/${enc(id)}`, { signal }),
  importance(metric: string, sweep: string | null, signal?: AbortSignal) {
    const q = new URLSearchParams({ metric });
    if (sweep) q.set('sweep', sweep);
    return request<Importance>(`/api/v1/importance?${q.toString()}`, { signal });
  },
  projection: (body: ProjectionRequest, signal?: AbortSignal) => post<Projection>('/api/v1/projections', body, signal),
  compare: async (body: CompareRequest, signal?: AbortSignal) => parseCompare(await post<unknown>('/api/v1/compare', body, signal)),
};

// ---------- comparison parsing ----------

/** A wire number: finite numbers as they are, "Infinity"/"-Infinity" as ±∞, anything else NaN. */
export function wireNumber(v: unknown): number {
  if (typeof v === 'number') return Number.isFinite(v) ? v : NaN;
  if (v === 'Infinity' || v === '+Infinity' || v === 'inf') return Infinity;
  if (v === '-Infinity' || v === '-inf') return -Infinity;
  return NaN;
}

function numbers(v: unknown, n: number): Float64Array {
  const out = new Float64Array(n).fill(NaN);
  if (!Array.isArray(v)) return out;
  for (let i = 0; i < Math.min(n, v.length); i++) out[i] = wireNumber(v[i]);
  return out;
}

const STATES: readonly TrackerState[] = ['SEARCH', 'TRACK', 'LOST'];

function stateOf(code: unknown, names: readonly string[]): TrackerState | null {
  const name = typeof code === 'number' ? names[code] : typeof code === 'string' ? code : undefined;
  return name && (STATES as readonly string[]).includes(name) ? (name as TrackerState) : null;
}

function obj(v: unknown): Record<string, unknown> {
  return v && typeof v === 'object' && !Array.isArray(v) ? (v as Record<string, unknown>) : {};
}

function valueRows(v: unknown): ValueRow[] {
  if (!Array.isArray(v)) return [];
  return v.map((r) => {
    const o = obj(r);
    const values = Array.isArray(o.values) ? o.values.map(wireNumber) : [];
    const finite = values.filter((x) => !Number.isNaN(x));
    const differs = typeof o.differs === 'boolean' ? o.differs : finite.length > 0 && (finite.some((x) => x !== finite[0]) || finite.length !== values.length);
    return { name: String(o.name ?? ''), values, differs };
  });
}

/**
 * POST /api/v1/compare's body → Comparison. Series are cut or padded (NaN) to `frames`; state codes
 * become names through state_names (default SEARCH, TRACK, LOST); a disagreement's worst teat is read
 * from `worst_teat` (an index, or a name of teat_names) when present.
 */
export function parseCompare(body: unknown): Comparison {
  const b = obj(body);
  const frames = Math.max(0, Math.floor(Number(b.frames) || 0));
  const names = Array.isArray(b.state_names) ? b.state_names.map(String) : [...STATES];
  const runs: CompareRun[] = (Array.isArray(b.runs) ? b.runs : []).map((r) => {
    const o = obj(r);
    return {
      id: String(o.id ?? ''),
      sweep: typeof o.sweep === 'string' ? o.sweep : null,
      origin: typeof o.origin === 'string' ? o.origin : undefined,
      summary: o.summary ? (o.summary as CompareRun['summary']) : undefined,
    };
  });
  const series: CompareSeries[] = (Array.isArray(b.series) ? b.series : []).map((s, k) => {
    const o = obj(s);
    const state: (TrackerState | null)[] = new Array<TrackerState | null>(frames).fill(null);
    if (Array.isArray(o.state)) for (let i = 0; i < Math.min(frames, o.state.length); i++) state[i] = stateOf(o.state[i], names);
    const teatErrorMm: Float64Array[] = [];
    if (Array.isArray(o.teat_error_mm) && o.teat_error_mm.length > 0) {
      for (let t = 0; t < 4; t++) teatErrorMm.push(new Float64Array(frames).fill(NaN));
      for (let i = 0; i < Math.min(frames, o.teat_error_mm.length); i++) {
        const row = o.teat_error_mm[i];
        if (!Array.isArray(row)) continue;
        for (let t = 0; t < 4; t++) teatErrorMm[t]![i] = wireNumber(row[t]);
      }
    }
    return {
      id: String(o.id ?? runs[k]?.id ?? `run ${k + 1}`),
      state,
      matches: numbers(o.matches, frames),
      verified: numbers(o.verified, frames),
      teatsMatched: numbers(o.teats_matched, frames),
      modelCost: numbers(o.model_cost, frames),
      shapeCost: numbers(o.shape_cost, frames),
      maxErrorMm: numbers(o.max_error_mm, frames),
      teatErrorMm,
    };
  });
  const teatNames = Array.isArray(b.teat_names) ? b.teat_names.map(String) : ['FL', 'FR', 'RL', 'RR'];
  const disagreements: Disagreement[] = (Array.isArray(b.disagreements) ? b.disagreements : []).map((d) => {
    const o = obj(d);
    // The worst teat by index or by name (teat_names, default FL FR RL RR).
    const wt = typeof o.worst_teat === 'string' ? teatNames.indexOf(o.worst_teat) : typeof o.worst_teat === 'number' ? o.worst_teat : NaN;
    return {
      frame: Math.floor(Number(o.frame) || 0),
      scoreMm: wireNumber(o.score_mm),
      states: Array.isArray(o.states) ? o.states.map((c) => stateOf(c, names)) : [],
      worstTeat: Number.isInteger(wt) && wt >= 0 && wt < 4 ? wt : null,
    };
  });
  return {
    video: String(b.video ?? ''),
    firstFrame: Math.max(0, Math.floor(Number(b.first_frame) || 0)),
    frames,
    runs: runs.length ? runs : series.map((s) => ({ id: s.id, sweep: null })),
    series,
    params: valueRows(b.params),
    results: valueRows(b.results),
    disagreements,
  };
}
