// The body of POST /api/v1/congestion from the dashboard's state: the data set, the time window (the
// data set's whole range without one), the callsign and ICAO24 filters, and either the grid over the map
// view and the altitude filter or a stored sector set, plus the panel's form.

import type { Filters } from '../../api/query';
import type { BBox } from '../../api/types';
import type { Compute, CongestionBody, Method } from './types';

export interface RequestInput {
  dataset: { id: string; t_min: number; t_max: number };
  filters: Filters;
  /** The map's view [w, s, e, n] (the grid's extent); null: the whole world. */
  mapBBox: BBox | null;
  /** A sector set's id, or null for the grid. */
  sectors: string | null;
  compute: Compute[];
  method: Method;
  /** The form's text fields by name (step, duration, peak, sustained, sustained_steps); '' = default. */
  fields: Record<string, string>;
}

const THRESHOLDS = ['peak', 'sustained', 'sustained_steps'] as const;

export function congestionBody(r: RequestInput): CongestionBody {
  const f = r.filters;
  const query: Record<string, string | number> = {
    t0: f.t0 ?? Math.floor(r.dataset.t_min),
    // [t0, t1) is half-open: the data set's last sample is at t_max.
    t1: f.t1 ?? Math.floor(r.dataset.t_max) + 1,
  };
  if (f.callsign) query.callsign = f.callsign;
  if (f.icao24) query.icao24 = f.icao24;
  let volumes: CongestionBody['volumes'];
  if (r.sectors !== null) volumes = { sectors: r.sectors };
  else {
    const grid: { bbox?: BBox; alt_min?: number; alt_max?: number; alt_unit?: 'ft' } = {};
    // 1e-4° (about 10 m) is plenty for a view and keeps the request short.
    if (r.mapBBox) grid.bbox = r.mapBBox.map((v) => Math.round(v * 1e4) / 1e4) as BBox;
    if (f.altMin !== null) grid.alt_min = f.altMin;
    if (f.altMax !== null) grid.alt_max = f.altMax;
    if (f.altMin !== null || f.altMax !== null) grid.alt_unit = 'ft';
    volumes = { grid };
  }
  const body: CongestionBody = { dataset: r.dataset.id, query, volumes, compute: [...r.compute], method: r.method };
  // Numbers are sent as numbers; anything else as typed, so that the server's parser names the field.
  const value = (text: string): number => {
    const n = Number(text);
    return (text !== '' && Number.isFinite(n) ? n : text) as number;
  };
  const step = r.fields.step?.trim() ?? '';
  const duration = r.fields.duration?.trim() ?? '';
  if (step) body.step = value(step);
  if (duration) body.duration = value(duration);
  const thresholds: NonNullable<CongestionBody['thresholds']> = {};
  for (const k of THRESHOLDS) {
    const v = r.fields[k]?.trim() ?? '';
    if (v) thresholds[k] = value(v);
  }
  if (Object.keys(thresholds).length) body.thresholds = thresholds;
  return body;
}

/**
 * The congestion map's tile template (GET /api/v1/datasets/{id}/congestion/tiles/{z}/{x}/{y}.png):
 * aircraft per pixel at instant `t`, or averaged over the window [t0, t1) when `t` is null, with the
 * callsign, ICAO24, altitude and ground filters, thresholded at `threshold` aircraft.
 */
export function congestionTileTemplate(origin: string, dataset: string, filters: Filters, t: number | null, threshold: number): string {
  const q = new URLSearchParams();
  if (t !== null) q.set('t', String(t));
  else {
    if (filters.t0 !== null) q.set('t0', String(filters.t0));
    if (filters.t1 !== null) q.set('t1', String(filters.t1));
  }
  if (filters.altMin !== null) q.set('alt_min', String(filters.altMin));
  if (filters.altMax !== null) q.set('alt_max', String(filters.altMax));
  if (filters.altMin !== null || filters.altMax !== null) q.set('alt_unit', 'ft');
  if (filters.callsign) q.set('callsign', filters.callsign);
  if (filters.icao24) q.set('icao24', filters.icao24);
  q.set('threshold', String(threshold));
  return `${origin}/api/v1/datasets/${encodeURIComponent(dataset)}/congestion/tiles/{z}/{x}/{y}.png?${q.toString()}`;
}
