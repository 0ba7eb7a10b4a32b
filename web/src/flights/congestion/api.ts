// The congestion REST calls (proto/openapi.yaml): sector sets, starting a congestion job, its result.
// Errors are api/client.ts's ApiError (the server's {error, detail, param}).

import type { FeatureCollection } from 'geojson';
import { fetchOk, request } from '../../api/client';
import type { CongestionAccepted, CongestionBody, CongestionResultWire, SectorSet } from './types';

const sectorPath = (id: string) => `/api/v1/sectors/${encodeURIComponent(id)}`;

export const congestionApi = {
  sectorSets: (signal?: AbortSignal) => request<{ sectors: SectorSet[] }>('/api/v1/sectors', { signal }),

  /** The stored GeoJSON of a set, as uploaded. */
  sectorGeojson: (id: string, signal?: AbortSignal) => request<FeatureCollection>(sectorPath(id), { signal }),

  /** Uploads a GeoJSON FeatureCollection of sectors (validated by the server: 422 names the feature). */
  uploadSectors(file: Blob, name: string) {
    const q = name ? `?${new URLSearchParams({ name }).toString()}` : '';
    return request<SectorSet>(`/api/v1/sectors${q}`, { method: 'POST', headers: { 'Content-Type': 'application/geo+json' }, body: file });
  },

  deleteSectors: (id: string) => request<void>(sectorPath(id), { method: 'DELETE' }),

  start: (body: CongestionBody) =>
    request<CongestionAccepted>('/api/v1/congestion', { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body) }),

  result: (job: string, signal?: AbortSignal) => request<CongestionResultWire>(`/api/v1/congestion/${encodeURIComponent(job)}`, { signal }),

  /** One CSV table of a result: series, hotspots, complexity or separation. */
  async csv(job: string, table: 'series' | 'hotspots' | 'complexity' | 'separation', signal?: AbortSignal): Promise<string> {
    const res = await fetchOk(`/api/v1/congestion/${encodeURIComponent(job)}?format=csv&table=${table}`, { signal });
    return res.text();
  },

  /** The CSV table's URL (a download link). */
  csvUrl: (job: string, table: string) => `/api/v1/congestion/${encodeURIComponent(job)}?format=csv&table=${encodeURIComponent(table)}`,
};
