// Wire types of the runs dashboard: stored tracker runs, sweeps, parameter importance, projections of
// the runs table (POST /api/v1/projections) and run comparisons (POST /api/v1/compare).

import type { TrackerState } from './trackerLog';

export interface RunAccuracy {
  frames_all_within?: number | null;
  mean_error_mm?: number | null;
  median_error_mm?: number | null;
  p95_error_mm?: number | null;
  reported_pairs?: number;
  visible_pairs?: number;
  within_mm?: number;
}

export interface RunSummary {
  frames: number;
  fps?: number;
  duration_s?: number;
  tracker_fps?: number;
  track_share: number;
  lost_episodes: number;
  has_truth?: boolean;
  accuracy: RunAccuracy | null;
}

/** A row of GET /api/v1/runs. */
export interface RunRow {
  id: string;
  run_id?: string;
  video: string;
  origin?: string;
  sweep: string | null;
  created?: string;
  tracker_version?: string;
  param_names: string[];
  params: number[];
  bytes?: number;
  summary: RunSummary;
}

export interface SweepAxisSpec {
  param: string;
  min?: number;
  max?: number;
  steps?: number;
}

export interface SweepSpecBody {
  mode?: 'grid' | 'random';
  samples?: number;
  seed?: number;
  base?: Record<string, number>;
  axes: SweepAxisSpec[];
}

export interface Sweep {
  id: string;
  created?: string;
  done?: boolean;
  state?: string;
  job?: string | null;
  runs: string[];
  total?: number;
  videos?: string[];
  spec?: SweepSpecBody;
}

export interface ImportanceInput {
  name: string;
  pearson: number | null;
  spearman: number | null;
  forest: number | null;
}

export interface Importance {
  metric: string;
  sweep: string | null;
  samples: number;
  forest_r2: number | null;
  inputs: ImportanceInput[];
}

export type ProjectionMethod = 'pca' | 'mds' | 'tsne' | 'lamp' | 'force';
export const PROJECTION_METHODS: readonly ProjectionMethod[] = ['pca', 'mds', 'tsne', 'lamp', 'force'];

export interface ProjectionRequest {
  runs?: { sweep?: string; ids?: string[]; include?: ('params' | 'metrics')[] };
  table?: { columns: string[]; rows: number[][] };
  method?: ProjectionMethod;
  perplexity?: number;
  iterations?: number;
  seed?: number;
  k?: number;
  standardize?: boolean;
  backend?: 'auto' | 'cpu' | 'opencl';
}

export interface ProjectionQuality {
  k?: number;
  trustworthiness?: number | null;
  continuity?: number | null;
  neighborhood_preservation?: number | null;
  stress?: number | null;
  shepard?: number | null;
  sampled?: boolean | number;
  queries?: number;
}

export interface Projection {
  method: string;
  rows: number;
  columns: string[];
  row_ids: string[] | null;
  dropped_columns?: { name: string; why: string }[];
  path?: string;
  variant?: string;
  timings_ms?: Record<string, number>;
  quality?: ProjectionQuality;
  coordinates: [number, number][];
}

/** Wire form of one run's series in a comparison: numbers may be null (no value) or "Infinity". */
export type WireNumber = number | null | string;

export interface CompareRequest {
  runs: string[];
  top?: number;
  miss_mm?: number;
}

/** A comparison parsed for drawing (parseCompare): NaN = no value, +Infinity = a visible teat not reported. */
export interface CompareSeries {
  id: string;
  /** Per frame: the tracker state (null where the name is unknown). */
  state: (TrackerState | null)[];
  matches: Float64Array;
  verified: Float64Array;
  teatsMatched: Float64Array;
  modelCost: Float64Array;
  shapeCost: Float64Array;
  maxErrorMm: Float64Array;
  /** [teat][frame] (FL FR RL RR), NaN where not scored; empty when the run has no ground truth. */
  teatErrorMm: Float64Array[];
}

export interface CompareRun {
  id: string;
  sweep: string | null;
  origin?: string;
  summary?: RunSummary;
}

export interface ValueRow {
  name: string;
  /** NaN where a run has no value. */
  values: number[];
  differs: boolean;
}

export interface Disagreement {
  frame: number;
  scoreMm: number;
  states: (TrackerState | null)[];
  worstTeat: number | null;
}

export interface Comparison {
  video: string;
  firstFrame: number;
  frames: number;
  runs: CompareRun[];
  series: CompareSeries[];
  params: ValueRow[];
  results: ValueRow[];
  disagreements: Disagreement[];
}
