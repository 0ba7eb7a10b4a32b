// Wire types of the gaze routes (/api/v1/gaze…, proto/openapi.yaml): gaze data sets and their recordings,
// detected events, scanpaths, areas of interest. Times are milliseconds on the tracker's clock; positions
// are stimulus (screen) pixels, origin top-left, y down, unless a recording's units are "deg".

export type GazeMethod = 'ivt' | 'idt' | 'adaptive';
export const GAZE_METHODS: readonly GazeMethod[] = ['ivt', 'idt', 'adaptive'];

export type GazeEventType = 'fixation' | 'saccade' | 'pso' | 'pursuit' | 'blink' | 'undefined';
export const GAZE_EVENT_TYPES: readonly GazeEventType[] = ['fixation', 'saccade', 'pso', 'pursuit', 'blink', 'undefined'];

/** The formats compute/gaze/ingest reads (`format=`; absent or auto: detected by content). */
export type GazeFormat = 'auto' | 'eyelink_asc' | 'tobii_tsv' | 'psychopy_tobii' | 'smi_idf_text' | 'gazecom_arff' | 'dsf_coord' | 'simple_gaze_tracker' | 'plain';

export interface GazeGeometry {
  width_px: number | null;
  height_px: number | null;
  width_cm: number | null;
  height_cm: number | null;
  distance_cm: number | null;
}

export interface GazeRecording {
  index: number;
  participant: string;
  stimulus: string;
  trial: string;
  format: string;
  units: 'px' | 'deg';
  rate_hz: number | null;
  samples: number;
  valid_samples: number;
  /** First and last sample's time on the tracker's clock (null for a recording without samples). */
  t0_ms: number | null;
  t1_ms: number | null;
  geometry: GazeGeometry;
  tracker_events?: number;
  /** Per-sample label columns of the file (e.g. coders' labels). */
  annotations?: string[];
}

/** An uploaded stimulus image (PUT /gaze/{id}/stimulus answers one; GET /gaze/{id} lists them). */
export interface GazeStimulusImage {
  stimulus: string;
  file: string;
  content_type: 'image/png' | 'image/jpeg';
  width_px: number;
  height_px: number;
  bytes: number;
}

/** One gaze data set of GET /gaze (the list) and GET /gaze/{id} (with its recordings). */
export interface GazeDataset {
  id: string;
  name: string;
  format: string;
  created: string;
  owner?: string;
  /** How many recordings (the list of them is `recording_list` on GET /gaze/{id}). */
  recordings: number;
  samples: number;
  participants: string[];
  stimuli: string[];
  recording_list?: GazeRecording[];
  /** Size of the stored recordings file (bytes). */
  bytes?: number;
  /** The stimuli's uploaded images (GET /gaze/{id}). */
  stimulus_images?: GazeStimulusImage[];
}

export interface GazeDatasetList {
  datasets: GazeDataset[];
}

/** The filters every gaze read route shares (one parser on the server). */
export interface GazeFilters {
  participant?: string | null;
  stimulus?: string | null;
  recording?: number | null;
  /** Window relative to each recording's first sample (ms). */
  t0_ms?: number | null;
  t1_ms?: number | null;
  method?: GazeMethod | null;
}

export interface GazeEvent {
  recording: number;
  type: GazeEventType;
  t_start_ms: number;
  t_end_ms: number;
  duration_ms: number;
  x: number | null;
  y: number | null;
  x_end: number | null;
  y_end: number | null;
}

export interface GazeEvents {
  events: GazeEvent[];
  counts: Partial<Record<GazeEventType, number>>;
  method: GazeMethod;
}

export interface Fixation {
  /** The centroid; null when the fixation has no valid sample position. */
  x: number | null;
  y: number | null;
  t_start_ms: number;
  duration_ms: number;
}

export interface Scanpath {
  recording: number;
  participant: string;
  stimulus: string;
  fixations: Fixation[];
}

export interface Scanpaths {
  method?: GazeMethod;
  scanpaths: Scanpath[];
}

/** An area of interest in stimulus pixels: a rectangle [x0, y0, x1, y1] or a polygon. */
export type Aoi = { name: string; rect: [number, number, number, number] } | { name: string; polygon: [number, number][] };

export interface AoiStats {
  name: string;
  fixations: number;
  dwell_ms: number;
  visitors: number;
  first_fixation_ms: { median: number | null; min: number | null };
  mean_fixation_ms: number | null;
}

export interface AoiAnswer {
  aois: AoiStats[];
  /** counts[i][j]: consecutive fixations going from AOI names[i] to names[j]. */
  transitions: { names: string[]; counts: number[][] };
  /** Recordings and fixations selected by the filters; `outside`: of those fixations, in no AOI. */
  recordings: number;
  fixations?: number;
  outside?: number;
  method?: GazeMethod;
}

/** What the stimulus-space density tiles count. */
export type GazeTileWhat = 'samples' | 'fixations';
