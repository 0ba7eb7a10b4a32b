// The flight dashboard's state: one store; its panels subscribe and read what they need.

import type { BBox, Dataset } from '../api/types';
import { DEFAULT_RENDER, EMPTY_FILTERS, type Filters, type RenderOptions } from '../api/query';

export interface AppState {
  datasets: Dataset[];
  datasetId: string | null;
  filters: Filters;
  render: RenderOptions;
  /** Send the current map view as bbox. */
  useMapView: boolean;
  /** The map's current bounds (kept up to date by the map view). */
  mapBBox: BBox | null;
  selectedFlight: number | null;
}

type Listener = (s: AppState, prev: AppState) => void;

export class Store {
  private state: AppState;
  private listeners = new Set<Listener>();

  constructor(initial: Partial<AppState> = {}) {
    this.state = {
      datasets: [],
      datasetId: null,
      filters: { ...EMPTY_FILTERS },
      render: { ...DEFAULT_RENDER },
      useMapView: false,
      mapBBox: null,
      selectedFlight: null,
      ...initial,
    };
  }

  get(): AppState {
    return this.state;
  }

  dataset(): Dataset | null {
    const s = this.state;
    return s.datasets.find((d) => d.id === s.datasetId) ?? null;
  }

  /** The filters as sent: the map view becomes the bbox when "use map view" is on. */
  effectiveFilters(): Filters {
    const s = this.state;
    return { ...s.filters, bbox: s.useMapView ? s.mapBBox : null };
  }

  set(patch: Partial<AppState>): void {
    const prev = this.state;
    this.state = { ...prev, ...patch };
    for (const l of this.listeners) l(this.state, prev);
  }

  setFilters(patch: Partial<Filters>): void {
    this.set({ filters: { ...this.state.filters, ...patch } });
  }

  setRender(patch: Partial<RenderOptions>): void {
    this.set({ render: { ...this.state.render, ...patch } });
  }

  subscribe(l: Listener): () => void {
    this.listeners.add(l);
    return () => this.listeners.delete(l);
  }
}
