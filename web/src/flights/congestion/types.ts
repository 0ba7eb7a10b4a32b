// Wire types of the congestion API (proto/openapi.yaml): stored sector sets (GET/POST/DELETE
// /api/v1/sectors), the body of POST /api/v1/congestion and its result (GET /api/v1/congestion/{job}).
// Times are Unix seconds; altitudes metres; counts are flights. The definitions of every figure are in
// compute/include/trailscope/congestion/counts.hpp and separation.hpp.

import type { Job } from '../../api/types';

/** A stored sector set (its metadata, as listed). */
export interface SectorSet {
  id: string;
  name: string;
  created: string;
  bytes?: number;
  sectors: number;
  vertices?: number;
  names?: string[];
  bbox?: [number, number, number, number];
  lower_fl?: number;
  upper_fl?: number;
}

export type Compute = 'occupancy' | 'entries' | 'hotspots' | 'complexity' | 'separation';
export type Method = 'interpolated' | 'samples';

/** The body of POST /api/v1/congestion. */
export interface CongestionBody {
  dataset: string;
  query: Record<string, string | number>;
  volumes: { grid: { bbox?: [number, number, number, number]; alt_min?: number; alt_max?: number; alt_unit?: 'ft' | 'm' } } | { sectors: string };
  compute: Compute[];
  step?: number;
  duration?: number;
  method?: Method;
  entry_window?: number;
  entry_step?: number;
  thresholds?: { peak?: number; sustained?: number; sustained_steps?: number };
}

export interface CongestionAccepted {
  job: Job;
  /** The result's path, /api/v1/congestion/{job}. */
  congestion: string;
}

/** A sparse series as the API sends it: indices with a non-zero value, ascending. */
export interface WireSeries {
  step?: number[];
  window?: number[];
  count: number[];
}

export interface WireVolume {
  id: string;
  kind: 'cell' | 'sector';
  south: number;
  north: number;
  west: number;
  east: number;
  lower_m: number;
  upper_m: number;
  peak: number | null;
  sustained: number | null;
  max_occupancy: number;
  total_entries: number;
  occupancy: WireSeries;
  entries: WireSeries;
}

export interface HotspotFlight {
  id: number;
  callsign: string;
  icao24: string;
}

export type HotspotKind = 'peak' | 'sustained';

export interface WireHotspot {
  /** The volume's id. */
  volume: string;
  kind: HotspotKind;
  first_step: number;
  last_step: number;
  start: number;
  end: number;
  peak: number;
  peak_time: number;
  threshold: number;
  excess: number;
  flights: HotspotFlight[];
}

export interface WireCounts {
  t0: number;
  t1: number;
  step: number;
  duration: number;
  method: Method;
  entry_window: number;
  entry_step: number;
  volumes_kind: 'grid' | 'sectors';
  steps: number;
  entry_windows: number;
  hours: number;
  flights: number;
  volumes: WireVolume[];
  hotspots: WireHotspot[];
  hotspots_total: number;
  complexity: unknown;
}

export interface CpaPoint {
  lat: number;
  lon: number;
  alt_m: number;
}

export interface SeparationEvent {
  flight_a: number;
  flight_b: number;
  icao24_a: string;
  callsign_a: string;
  icao24_b: string;
  callsign_b: string;
  t_start: number;
  t_end: number;
  duration_s: number;
  clipped_start: boolean;
  clipped_end: boolean;
  cpa: { t: number; horizontal_m: number; vertical_m: number; a: CpaPoint; b: CpaPoint };
  min_vertical_m: number;
}

export interface WireSeparation {
  t0: number;
  t1: number;
  flights: number;
  count: number;
  events: SeparationEvent[];
}

/** GET /api/v1/congestion/{job} as JSON. */
export interface CongestionResultWire {
  job?: string;
  dataset: string;
  volumes: CongestionBody['volumes'];
  compute: Compute[];
  counts: WireCounts | null;
  separation: WireSeparation | null;
}
