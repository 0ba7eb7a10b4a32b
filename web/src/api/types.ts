// Wire types of the TrailScope REST API (proto/openapi.yaml) and of the job WebSocket: data sets, summaries,
// flights, bundles and jobs.
// Times are Unix seconds (UTC); distances and altitudes are metres unless a field says otherwise.

export interface ApiErrorBody {
  error: string;
  detail: string;
  /** The query parameter the error is about, when there is one (e.g. "t0"). */
  param?: string;
}

export interface Health {
  status: string;
  version: string;
  opencl: { available: boolean; device?: string };
}

/** [west, south, east, north] in WGS84 degrees. */
export type BBox = [number, number, number, number];

export interface Dataset {
  id: string;
  name: string;
  format: string;
  flights: number;
  points: number;
  t_min: number;
  t_max: number;
  bbox: BBox;
  alt_max_m: number;
  created: string;
  ingest?: Record<string, unknown>;
}

export interface DatasetList {
  datasets: Dataset[];
}

export type JobState = 'queued' | 'running' | 'done' | 'failed' | 'cancelled';

export interface Job {
  id: string;
  kind: string;
  state: JobState;
  /** 0..1 */
  progress: number;
  stage: string;
  dataset: string;
  error: ApiErrorBody | null;
  /** The job's result once done (an ingest's Dataset, a bundle's Bundle). */
  result?: unknown;
}

export interface JobAccepted {
  job: Job;
}

export interface TimeHistogram {
  t0: number;
  bin_seconds: number;
  counts: number[];
}

export interface AltitudeHistogram {
  unit: 'ft' | 'm';
  bin_width: number;
  min: number;
  counts: number[];
}

export interface SpeedStats {
  unit: string;
  /** Points with a speed; min..p95 are 0 when it is 0. */
  count?: number;
  min: number;
  max: number;
  mean: number;
  p50: number;
  p95: number;
}

export interface CallsignCount {
  callsign: string;
  flights: number;
  points: number;
}

export interface Summary {
  dataset: string;
  flights: number;
  points: number;
  t_min: number | null;
  t_max: number | null;
  time_histogram: TimeHistogram;
  altitude_histogram: AltitudeHistogram;
  speed: SpeedStats | null;
  top_callsigns: CallsignCount[];
  /** The server's canonical form of the query it answered. */
  query?: string;
  elapsed_ms: number;
  /** Physically implausible values among the matching points (counts and the largest examples). */
  quality?: QualityReport;
}

export interface QualityExample {
  flight_id: number;
  callsign: string;
  t: number;
  /** m/s for speeds and jumps, metres for altitudes. */
  value: number;
  value_kt?: number;
  value_fl?: number;
}

export interface QualityCount {
  count: number;
  examples: QualityExample[];
}

export interface QualityReport {
  limits?: { speed_ms?: number; speed_kt?: number; altitude_m?: number; altitude_fl?: number };
  speed: QualityCount;
  altitude: QualityCount;
  jumps: QualityCount;
}

/** A flight of the list: "in window" columns cover its points passing the filters, flight_* the whole flight. */
export interface FlightRow {
  id: number;
  icao24: string;
  callsign: string;
  t_start: number;
  t_end: number;
  points: number;
  alt_max_m: number;
  duration_s?: number;
  flight_t_start?: number;
  flight_t_end?: number;
  flight_duration_s?: number;
  flight_points?: number;
}

/** The flight list's sort columns (GET …/flights `sort`). */
export const FLIGHT_SORTS = [
  'id',
  'icao24',
  'callsign',
  't_start',
  't_end',
  'duration_s',
  'points',
  'alt_max_m',
  'flight_t_start',
  'flight_t_end',
  'flight_duration_s',
  'flight_points',
] as const;
export type FlightSort = (typeof FLIGHT_SORTS)[number];
export type SortOrder = 'asc' | 'desc';

export interface FlightPage {
  total: number;
  page: number;
  page_size: number;
  sort?: FlightSort;
  order?: SortOrder;
  flights: FlightRow[];
}

export interface FlightProperties {
  id: number;
  icao24: string;
  callsign: string;
  times: number[];
  altitudes_m: (number | null)[];
  speeds_ms: (number | null)[];
}

export interface FlightFeature {
  type: 'Feature';
  geometry: { type: 'LineString'; coordinates: [number, number, number?][] };
  properties: FlightProperties;
}

export type WsMessage = { type: 'job'; job: Job } | { type: string; [k: string]: unknown };

export type DensityValue = 'count' | 'altitude' | 'speed';
export type DensityHow = 'linear' | 'log' | 'eq_hist';
export type Colormap = 'fire' | 'viridis' | 'inferno' | 'magma' | 'gray';
export type DatasetFormat = 'opensky_csv' | 'traffic_json' | 'so6' | 'readsb_trace';

/** One bundling parameter (GET /api/v1/bundles/params), as BundleParams describes it. */
export interface BundleParamInfo {
  name: string;
  type: 'number' | 'integer' | 'boolean' | 'enum';
  default: string;
  /** "[2, 128] px", "1..100", "uniform, hourglass", ... */
  range: string;
  help: string;
}

export interface BundleParamList {
  params: BundleParamInfo[];
  render: string[];
}

export interface BundleQuality {
  ink_raw_px: number;
  ink_bundled_px: number;
  /** 1 − bundled/raw */
  ink_reduction: number;
  mean_displacement_px: number;
  max_displacement_px: number;
}

/** A stored bundling result (GET /api/v1/bundles/{id}). */
export interface Bundle {
  id: string;
  created: string;
  source: { dataset?: string; query?: Record<string, string>; canonical?: string; graph?: string; name?: string };
  units: 'merc32' | 'epsg3857' | 'plane';
  coordinates: 'lonlat' | 'source';
  params: Record<string, string>;
  polylines: number;
  input_points: number;
  points: number;
  quality: BundleQuality;
  times_ms: Record<'resample' | 'splat' | 'convolve' | 'advect' | 'smooth' | 'endpoints' | 'post' | 'total', number>;
  path: string;
  device: string;
}

export interface BundleAccepted {
  job: Job;
  /** The id the result will have once the job is done. */
  bundle: string;
}
