// The public interface of the flight animation layer (trafficAnimation.ts implements it): what the
// playback UI (time cursor, transport, legend, hover/click/follow, filters) may call. Times are float64
// Unix seconds everywhere on this side; only chunk-relative float32 times reach the GPU
// (proto/animation_chunks.md), so there is no float32 epoch jitter at any time of day.

/** Client-side filters applied during playback without refetching (GPU uniforms / per-flight masks). */
export interface TrafficFilter {
  /** Altitude band in metres, edges included; an unknown altitude fails any band (as the API's filter). */
  altMinM?: number;
  altMaxM?: number;
  /**
   * Callsign pattern, the API's rule (compute's callsign_matches): `*` any run, `?` one character, no
   * wildcard = prefix; case-insensitive. Flights without callsign fail a non-empty pattern.
   */
  callsign?: string;
  /** ICAO 24-bit addresses (hex, any case); a flight passes when its address is one of them. */
  icao24?: string[];
  /** [west, south, east, north] in degrees; west > east crosses 180°. Applies to the drawn position. */
  bbox?: [number, number, number, number];
}

export type ColorBy = 'altitude' | 'speed' | 'vrate' | 'callsign';

/** One legend entry: a numeric value (in `unit`) or a callsign prefix, and its CSS colour. */
export interface LegendStop {
  value: number | string;
  color: string;
}

export interface Legend {
  colorBy: ColorBy;
  /** 'm' (altitude), 'm/s' (speed, vertical rate) or '' (callsign prefix). */
  unit: string;
  stops: LegendStop[];
}

/** An aircraft under the pointer (pick) or selected. Unknown numbers are NaN. */
export interface PickedAircraft {
  flightId: number;
  callsign: string;
  icao24: string;
  lon: number;
  lat: number;
  altM: number;
  speedMs: number;
  trackDeg: number;
  vrateMs: number;
}

/** A drawn aircraft at an instant (positionsAt), as the API's GET .../positions?t= would give it. */
export interface DrawnPosition {
  flightId: number;
  lon: number;
  lat: number;
  altM: number;
}

export interface AnimationStats {
  chunksInMemory: number;
  bytesInMemory: number;
  /** Aircraft drawn at the current instant (after filters). */
  aircraft: number;
  /** Chunks being fetched. */
  pending: number;
}


export interface TrafficAnimationOptions {
  /** Chunk length in seconds (the route's duration; aligned chunk starts). Default 300. */
  chunkSeconds?: number;
  /** Tail (trail fragment) length in seconds, 0..1800. Default 120. */
  tailSeconds?: number;
  colorBy?: ColorBy;
  /** The fetch to use (tests inject one). Default: window.fetch. */
  fetch?: typeof fetch;
  /** Base URL of the API (default: same origin, ''). */
  baseUrl?: string;
  /** Chunks to keep ahead of the playhead (default 1; the UI raises it at high speeds via setLookahead). */
  lookaheadChunks?: number;
  /** Map layer id to insert the layer before (default: on top). */
  beforeId?: string;
  /** The dataset's [t_min, t_max] (Unix seconds): chunks wholly outside are never requested. */
  span?: [number, number] | null;
}

/**
 * The animation layer on a MapLibre map: `new TrafficAnimation(map, datasetId, opts)`.
 * It adds one custom layer to the map and removes it in destroy().
 */
export interface TrafficAnimationApi {
  /** Moves the playhead (float64 Unix seconds); fetches the chunks it needs ahead and behind. */
  setTime(tUnix: number): void;
  /** The playhead. */
  time(): number;
  /** Tail length in seconds, clamped to [0, 1800]. */
  setTail(seconds: number): void;
  /** How many seconds of data to keep ahead of the playhead (e.g. speed × 2 s while playing); >= 0. */
  setLookahead(seconds: number): void;
  setColorBy(c: ColorBy): void;
  legend(): Legend;
  setFilter(f: TrafficFilter): void;
  /** Highlights a flight (drawn on top, larger); null clears. */
  setSelected(flightId: number | null): void;
  /** Whether the layer draws (hidden layers keep their chunks). */
  setVisible(v: boolean): void;
  /** The aircraft nearest to a screen point (CSS px, map container coordinates) within 12 px, or null. */
  pick(point: { x: number; y: number }): PickedAircraft | null;
  /** A flight's state at the playhead (for follow and the selected card), or null when it is not flying. */
  aircraft(flightId: number): PickedAircraft | null;
  /** What is drawn at `tUnix` (loaded chunks only; after filters), ordered by flight id. */
  positionsAt(tUnix: number): DrawnPosition[];
  /** Resolves when the chunk holding `tUnix` (and the tail's chunks) are loaded; rejects on an API error. */
  ready(tUnix: number): Promise<void>;
  /** Called after every change of the cache or of the drawn set (at most once per frame). */
  onStats(cb: (s: AnimationStats) => void): void;
  /** Called when a chunk request fails (an ApiError from api/client.ts). */
  onError(cb: (err: Error) => void): void;
  destroy(): void;
}
