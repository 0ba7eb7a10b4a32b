// Wire types of the tracker API: videos, tracker parameters, live replays and their WebSocket.
// The per-frame tracker record and the ground truth are decoded by trackerLog.ts (protobuf JSON omits
// default values, so those are not trusted as typed here).

export interface Intrinsics {
  width: number;
  height: number;
  fx: number;
  fy: number;
  cx: number;
  cy: number;
}

export interface Video {
  id: string;
  name: string;
  frame_count: number;
  fps: number;
  intrinsics: Intrinsics;
  has_truth: boolean;
  /** One colour range for every frame, mm [near, far] (videos stored before it existed lack it). */
  depth_range_mm?: [number, number];
  source?: { scenario?: string; [k: string]: unknown };
}

export interface TrackerParam {
  name: string;
  unit: string;
  default_value: number;
  min: number;
  max: number;
  integer: boolean;
  help: string;
}

export interface Replay {
  id: string;
  video: string;
  frames: number;
  fps: number;
  width: number;
  height: number;
  params: Record<string, number>;
  /** WebSocket path, e.g. "/api/v1/replays/{id}/ws". */
  ws: string;
  /** Frames the server has computed so far (GET only). */
  computed?: number;
  done?: boolean;
  /** The stored run's id once the log is kept. */
  run?: string | null;
  has_truth?: boolean;
  /** Depth colour map and the depth range it spans (mm). */
  colormap?: string;
  depth_range_mm?: [number, number];
  /** The error body of a failed run, or null. */
  error?: { error: string; detail: string } | null;
  viewers?: number;
}

/** One viewer's cursor as the server reports it. */
export interface PlayerState {
  playing: boolean;
  frame: number;
  speed: number;
  computed?: number;
  done?: boolean;
}

/** Client → server operations on the replay WebSocket. */
export type ReplayOp =
  | { op: 'play' }
  | { op: 'pause' }
  | { op: 'seek'; frame: number }
  | { op: 'step'; delta: number }
  | { op: 'speed'; value: number };

export const SPEED_MIN = 0.1;
export const SPEED_MAX = 16;
