// Typed client of the gaze routes (/api/v1/gaze…): the store (list, one data set, upload, delete, the
// stimulus image), the read routes under the shared filters (events, scanpaths, areas of interest), the
// stimulus-space density tiles and the saccade bundling job. Query building is pure (gazeQuery, tileUrl),
// unit-tested in gaze.test.ts.

import { request, uploadFile, type UploadHandle } from './client';
import type { BundleAccepted } from './types';
import type { DensityLegendAnswer } from '../lib/legend';
import type { Aoi, AoiAnswer, GazeDataset, GazeDatasetList, GazeEvents, GazeEventType, GazeFilters, GazeFormat, GazeStimulusImage, GazeTileWhat, Scanpaths } from './gazeTypes';

export const gazePath = (id: string) => `/api/v1/gaze/${encodeURIComponent(id)}`;

/**
 * The query string of the shared gaze filters: absent, null, empty and non-finite values are left out (the
 * server's defaults apply), numbers are written as they are, `method` only when not the default (ivt) is
 * implied by leaving it out.
 */
export function gazeQuery(f: GazeFilters, extra: Record<string, string | number | null | undefined> = {}): URLSearchParams {
  const q = new URLSearchParams();
  const put = (k: string, v: string | number | null | undefined) => {
    if (v === null || v === undefined) return;
    if (typeof v === 'number') {
      if (Number.isFinite(v)) q.set(k, String(v));
    } else if (v !== '') q.set(k, v);
  };
  put('participant', f.participant);
  put('stimulus', f.stimulus);
  put('recording', f.recording);
  put('t0_ms', f.t0_ms);
  put('t1_ms', f.t1_ms);
  put('method', f.method);
  for (const [k, v] of Object.entries(extra)) put(k, v);
  return q;
}

/** The filters as the JSON members of a POST body (AOIs, bundling): the same names as the query. */
export function gazeBodyFilters(f: GazeFilters): Record<string, string | number> {
  const out: Record<string, string | number> = {};
  for (const [k, v] of gazeQuery(f)) out[k] = k === 'recording' || k === 't0_ms' || k === 't1_ms' ? Number(v) : v;
  return out;
}

const withQuery = (path: string, q: URLSearchParams) => {
  const s = q.toString();
  return s ? `${path}?${s}` : path;
};

export interface GazeTileRender {
  what: GazeTileWhat;
  how: 'linear' | 'log' | 'eq_hist';
  cmap: string;
}

/**
 * The URL of stimulus-space density tile z/x/y of data set `id` (256-px tiles over the square of side
 * max(width, height) of the stimulus; tile 0/0/0 covers it, origin top-left).
 */
export function gazeTileUrl(id: string, z: number, x: number, y: number, f: GazeFilters, r: GazeTileRender): string {
  const q = gazeQuery(f, { what: r.what, how: r.how, cmap: r.cmap });
  return withQuery(`${gazePath(id)}/tiles/${z}/${x}/${y}.png`, q);
}

/** The URL of the stimulus image of `stimulus` in data set `id`. */
export function gazeStimulusUrl(id: string, stimulus: string): string {
  return withQuery(`${gazePath(id)}/stimulus`, new URLSearchParams({ stimulus }));
}

export interface GazeUploadOptions {
  name: string;
  format?: GazeFormat | '';
  participant?: string;
  stimulus?: string;
  width_px?: number;
  height_px?: number;
  width_cm?: number;
  height_cm?: number;
  distance_cm?: number;
}

/** POST /gaze's query: the name, and whatever of format, participant, stimulus and geometry is given. */
export function gazeUploadQuery(o: GazeUploadOptions): URLSearchParams {
  const q = new URLSearchParams({ name: o.name });
  for (const k of ['format', 'participant', 'stimulus'] as const) if (o[k]) q.set(k, o[k]);
  for (const k of ['width_px', 'height_px', 'width_cm', 'height_cm', 'distance_cm'] as const) {
    const v = o[k];
    if (v !== undefined && Number.isFinite(v) && v > 0) q.set(k, String(v));
  }
  return q;
}

export const gazeApi = {
  list: (signal?: AbortSignal) => request<GazeDatasetList>('/api/v1/gaze', { signal }),

  get: (id: string, signal?: AbortSignal) => request<GazeDataset>(gazePath(id), { signal }),

  remove: (id: string) => request<void>(gazePath(id), { method: 'DELETE' }),

  /** Uploads one gaze file as a new data set: resolves with the ingest job once the body is sent. */
  upload: (file: Blob, o: GazeUploadOptions, onProgress?: (fraction: number) => void): UploadHandle =>
    uploadFile(`/api/v1/gaze?${gazeUploadQuery(o).toString()}`, file, onProgress),

  /** Stores the image of `stimulus` (PNG or JPEG bytes). */
  putStimulus: (id: string, stimulus: string, image: Blob) =>
    request<GazeStimulusImage>(gazeStimulusUrl(id, stimulus), {
      method: 'PUT',
      headers: { 'Content-Type': image.type || 'application/octet-stream' },
      body: image,
    }),

  events(id: string, f: GazeFilters, types: readonly GazeEventType[], signal?: AbortSignal) {
    const q = gazeQuery(f, { type: types.length ? types.join(',') : null });
    return request<GazeEvents>(withQuery(`${gazePath(id)}/events`, q), { signal });
  },

  scanpaths: (id: string, f: GazeFilters, signal?: AbortSignal) =>
    request<Scanpaths>(withQuery(`${gazePath(id)}/scanpaths`, gazeQuery(f)), { signal }),

  aoi: (id: string, aois: readonly Aoi[], f: GazeFilters, signal?: AbortSignal) =>
    request<AoiAnswer>(`${gazePath(id)}/aoi`, {
      method: 'POST',
      headers: { 'Content-Type': 'application/json' },
      body: JSON.stringify({ aois, ...gazeBodyFilters(f) }),
      signal,
    }),

  /** The legend of the density tiles at zoom z (the span they are shaded with and their colours). */
  tilesLegend(id: string, f: GazeFilters, z: number, r: GazeTileRender, stops: number, signal?: AbortSignal) {
    const q = gazeQuery(f, { z, what: r.what, how: r.how, cmap: r.cmap, stops });
    return request<DensityLegendAnswer>(withQuery(`${gazePath(id)}/tiles/legend`, q), { signal });
  },

  /**
   * Starts bundling the selected saccades in stimulus pixels (a job); `params` as POST /bundles takes them
   * (left out: the defaults). The bundle is then read at /bundles/{bundle} (units "plane": stimulus px).
   */
  startBundle(id: string, f: GazeFilters, params: Record<string, string | number> = {}) {
    const body: Record<string, unknown> = gazeBodyFilters(f);
    if (Object.keys(params).length) body.params = params;
    return request<BundleAccepted>(`${gazePath(id)}/bundle`, {
      method: 'POST',
      headers: { 'Content-Type': 'application/json' },
      body: JSON.stringify(body),
    });
  },
};
