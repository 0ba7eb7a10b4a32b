// Typed client for the TrailScope REST API (same origin as the page: requests carry the session cookie).
import { notifyUnauthorized } from './session';

import type { DensityLegendAnswer } from '../lib/legend';
import type {
  ApiErrorBody,
  Bundle,
  BundleAccepted,
  BundleParamList,
  Dataset,
  DatasetFormat,
  DatasetList,
  FlightFeature,
  FlightPage,
  FlightSort,
  SortOrder,
  Health,
  Job,
  JobAccepted,
  Summary,
} from './types';

/** An error answered by the API (4xx/5xx with `{error, detail, param}`), or a transport failure (status 0). */
export class ApiError extends Error {
  readonly status: number;
  readonly code: string;
  readonly detail: string;
  readonly param: string | undefined;

  constructor(status: number, body: ApiErrorBody) {
    super(body.detail || body.error);
    this.name = 'ApiError';
    this.status = status;
    this.code = body.error;
    this.detail = body.detail;
    this.param = body.param;
  }
}

export function isAbort(e: unknown): boolean {
  return e instanceof DOMException && e.name === 'AbortError';
}

/** Parses an error body; falls back to the status line when the body is not the API's JSON. */
export async function errorFromResponse(res: Response): Promise<ApiError> {
  let body: ApiErrorBody = { error: `http_${res.status}`, detail: `${res.status} ${res.statusText}`.trim() };
  try {
    const text = await res.text();
    const parsed: unknown = text ? JSON.parse(text) : null;
    if (parsed && typeof parsed === 'object' && 'error' in parsed) body = parsed as ApiErrorBody;
  } catch {
    /* not JSON: keep the status line */
  }
  return new ApiError(res.status, body);
}

/**
 * fetch, with a network failure as ApiError(0, "network") (an abort is rethrown as it is) and, unless `ok`
 * accepts the status, a non-2xx answer as the server's ApiError.
 */
export async function fetchOk(path: string, init: RequestInit = {}, ok = (res: Response) => res.ok): Promise<Response> {
  let res: Response;
  try {
    res = await fetch(path, init);
  } catch (e) {
    if (isAbort(e)) throw e;
    throw new ApiError(0, { error: 'network', detail: 'The TrailScope server cannot be reached.' });
  }
  if (res.status === 401) notifyUnauthorized();
  if (!ok(res)) throw await errorFromResponse(res);
  return res;
}

/** A JSON request (undefined for 204 No Content); errors as fetchOk. */
export async function request<T>(path: string, init: RequestInit = {}): Promise<T> {
  const res = await fetchOk(path, { ...init, headers: { Accept: 'application/json', ...init.headers } });
  if (res.status === 204) return undefined as T;
  return (await res.json()) as T;
}

const ds = (id: string) => `/api/v1/datasets/${encodeURIComponent(id)}`;
const withQuery = (path: string, q: URLSearchParams) => {
  const s = q.toString();
  return s ? `${path}?${s}` : path;
};

export const api = {
  health: (signal?: AbortSignal) => request<Health>('/api/v1/health', { signal }),

  datasets: (signal?: AbortSignal) => request<DatasetList>('/api/v1/datasets', { signal }),

  dataset: (id: string, signal?: AbortSignal) => request<Dataset>(ds(id), { signal }),

  deleteDataset: (id: string) => request<void>(ds(id), { method: 'DELETE' }),

  summary(id: string, query: URLSearchParams, bins: number, signal?: AbortSignal) {
    const q = new URLSearchParams(query);
    q.set('bins', String(bins));
    return request<Summary>(withQuery(`${ds(id)}/summary`, q), { signal });
  },

  /** The legend of the density tiles at zoom z: values and colours of the shading applied. */
  densityLegend(id: string, query: URLSearchParams, z: number, r: { value: string; how: string; cmap: string }, stops: number, signal?: AbortSignal) {
    const q = new URLSearchParams(query);
    q.set('z', String(z));
    q.set('value', r.value);
    q.set('how', r.how);
    q.set('cmap', r.cmap);
    q.set('stops', String(stops));
    return request<DensityLegendAnswer>(withQuery(`${ds(id)}/density/legend`, q), { signal });
  },
  flights(id: string, query: URLSearchParams, page: number, pageSize: number, signal?: AbortSignal, sort?: { sort: FlightSort; order: SortOrder }) {
    const q = new URLSearchParams(query);
    q.set('page', String(page));
    q.set('page_size', String(pageSize));
    if (sort) {
      q.set('sort', sort.sort);
      q.set('order', sort.order);
    }
    return request<FlightPage>(withQuery(`${ds(id)}/flights`, q), { signal });
  },

  flight: (id: string, flightId: number, signal?: AbortSignal) =>
    request<FlightFeature>(`${ds(id)}/flights/${flightId}`, { signal }),

  job: (jobId: string, signal?: AbortSignal) => request<Job>(`/api/v1/jobs/${encodeURIComponent(jobId)}`, { signal }),

  cancelJob: (jobId: string) => request<Job | void>(`/api/v1/jobs/${encodeURIComponent(jobId)}`, { method: 'DELETE' }),

  bundleParams: (signal?: AbortSignal) => request<BundleParamList>('/api/v1/bundles/params', { signal }),

  /** Starts bundling the flight trails of a dataset window; `query` holds the summary route's filters. */
  startBundle(dataset: string, query: URLSearchParams, params: Record<string, string>) {
    const body = { source: { dataset, query: Object.fromEntries(query) }, params };
    return request<BundleAccepted>('/api/v1/bundles', {
      method: 'POST',
      headers: { 'Content-Type': 'application/json' },
      body: JSON.stringify(body),
    });
  },

  bundle: (id: string, signal?: AbortSignal) => request<Bundle>(`/api/v1/bundles/${encodeURIComponent(id)}`, { signal }),

  /** The bundle's TSBL polylines, fully bundled (the client blends toward the originals itself). */
  async bundlePolylines(id: string, signal?: AbortSignal): Promise<ArrayBuffer> {
    const res = await fetchOk(`/api/v1/bundles/${encodeURIComponent(id)}/polylines?format=binary&relaxation=0`, { signal });
    return res.arrayBuffer();
  },
};

/** XYZ template of a bundle's map tiles over `dataset` at `relaxation`. */
export function bundleTileTemplate(origin: string, dataset: string, bundle: string, relaxation: number, color = 'length'): string {
  const q = new URLSearchParams({ relaxation: relaxation.toFixed(2) });
  // The tiles' default colour (length) is left out, so its URLs (and cached tiles) stay as they were.
  if (color !== 'length') q.set('color', color);
  return `${origin}/tiles/${encodeURIComponent(dataset)}/bundle/${encodeURIComponent(bundle)}/{z}/{x}/{y}.png?${q.toString()}`;
}

export interface UploadHandle {
  /** Resolves with the accepted ingest job once the whole body is sent. */
  done: Promise<Job>;
  abort(): void;
}

/**
 * POSTs a raw file (plain or gzip) as a new data set. Uses XMLHttpRequest rather than fetch because
 * only XHR reports upload progress, which matters for files of hundreds of MB.
 */
export function uploadDataset(
  file: File,
  opts: { name: string; format?: DatasetFormat; onProgress?: (fraction: number) => void },
): UploadHandle {
  const q = new URLSearchParams({ name: opts.name });
  if (opts.format) q.set('format', opts.format);
  return uploadFile(`/api/v1/datasets?${q.toString()}`, file, opts.onProgress);
}

/**
 * POSTs `file` as the raw body to `url`, which answers 202 `{"job": …}` (an ingest job); `onProgress` gets
 * the fraction of the body sent (XMLHttpRequest: fetch reports no upload progress).
 */
export function uploadFile(url: string, file: Blob, onProgress?: (fraction: number) => void): UploadHandle {
  const xhr = new XMLHttpRequest();
  const done = new Promise<Job>((resolve, reject) => {
    xhr.open('POST', url);
    xhr.setRequestHeader('Content-Type', 'application/octet-stream');
    xhr.setRequestHeader('Accept', 'application/json');
    xhr.upload.onprogress = (e) => {
      if (e.lengthComputable && onProgress) onProgress(e.loaded / e.total);
    };
    xhr.onload = () => {
      if (xhr.status === 401) notifyUnauthorized();
      let body: unknown = null;
      try {
        body = JSON.parse(xhr.responseText);
      } catch {
        /* handled below */
      }
      if (xhr.status >= 200 && xhr.status < 300 && body && typeof body === 'object' && 'job' in body) {
        resolve((body as JobAccepted).job);
      } else if (body && typeof body === 'object' && 'error' in body) {
        reject(new ApiError(xhr.status, body as ApiErrorBody));
      } else {
        reject(new ApiError(xhr.status, { error: `http_${xhr.status}`, detail: `Upload failed (${xhr.status} ${xhr.statusText})` }));
      }
    };
    xhr.onerror = () => reject(new ApiError(0, { error: 'network', detail: 'Upload failed: the server cannot be reached.' }));
    xhr.onabort = () => reject(new DOMException('Upload cancelled', 'AbortError'));
    xhr.send(file);
  });
  return { done, abort: () => xhr.abort() };
}
