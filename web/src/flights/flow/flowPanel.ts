// The flow layer of the flight dashboard: "Show flows" fetches the flow map's streamlines of the current
// data set, window, filters and map view twice (GET /api/v1/datasets/{id}/flow?format=json, just above
// level 1 and at level 2: the same lines, resampled alike) and draws them as a MapLibre line layer,
// coloured by heading and weighted by traffic. The level slider then moves on the client (model.ts):
// 0 = the density tiles alone, 1 = the streamlines, 2 = their bundles.
// The server also draws these lines as XYZ tiles (GET /api/v1/datasets/{id}/flow/{z}/{x}/{y}.png) for other map
// clients; this layer keeps the geometry instead, so that the slider blends levels without a request per step.

import type * as maplibregl from 'maplibre-gl';
import { ApiError, isAbort, request } from '../../api/client';
import { buildQuery } from '../../api/query';
import { h, mount, sectionHead } from '../../lib/dom';
import type { Store } from '../state';
import type { ErrorSlots } from '../errors';
import { type FlowJson, levelOpacity, linesAt, toFeatures } from './model';

const SOURCE = 'flow-lines';
const LAYER = 'flow-lines';
/** The density tiles' layer (map.ts) and its own opacity, which the level scales. */
const DENSITY_LAYER = 'density';
const DENSITY_OPACITY = 0.92;
const EMPTY: GeoJSON.FeatureCollection = { type: 'FeatureCollection', features: [] };

export class FlowPanel {
  private readonly slider: HTMLInputElement;
  private readonly value: HTMLElement;
  private readonly status: HTMLElement;
  private readonly showBtn: HTMLButtonElement;
  private level = 2;
  private streams: FlowJson | null = null;
  private bundles: FlowJson | null = null;
  private ctrl: AbortController | null = null;

  constructor(
    private readonly root: HTMLElement,
    private readonly store: Store,
    private readonly map: maplibregl.Map,
    private readonly errors: ErrorSlots,
  ) {
    this.slider = h('input', { type: 'range', min: '0', max: '2', step: '0.01', value: '2', 'data-testid': 'flow-level', 'aria-label': 'Abstraction level' });
    this.value = h('span', { class: 'flow-level-value', 'data-testid': 'flow-level-value' }, '2.00');
    this.status = h('div', { class: 'flow-status', 'aria-live': 'polite', 'data-testid': 'flow-status' });
    this.showBtn = h('button', { type: 'button', class: 'btn primary', 'data-testid': 'flow-show' }, 'Show flows');
    this.showBtn.addEventListener('click', () => void this.load());
    this.slider.addEventListener('input', () => this.setLevel(Number(this.slider.value)));
    mount(
      root,
      sectionHead('Flow map'),
      h('p', { class: 'hint' }, 'Main flows of the window: density → streamlines → bundled streamlines.'),
      this.showBtn,
      h('label', { class: 'flow-level' }, 'Level ', this.slider, this.value),
      this.status,
    );
    root.dataset.state = 'idle';
    if (map.isStyleLoaded()) this.addLayer();
    else map.once('load', () => this.addLayer());
  }

  private addLayer() {
    if (this.map.getSource(SOURCE)) return;
    this.map.addSource(SOURCE, { type: 'geojson', data: EMPTY });
    this.map.addLayer({
      id: LAYER,
      type: 'line',
      source: SOURCE,
      layout: { 'line-cap': 'round', 'line-join': 'round' },
      paint: { 'line-color': ['get', 'color'], 'line-width': ['get', 'width'], 'line-opacity': 0 },
    });
  }

  private async load() {
    const d = this.store.dataset();
    if (!d) return;
    this.ctrl?.abort();
    const ctrl = (this.ctrl = new AbortController());
    const s = this.store.get();
    const q = buildQuery({ ...this.store.effectiveFilters(), bbox: s.mapBBox ?? this.store.effectiveFilters().bbox });
    q.set('format', 'json');
    const url = (level: string) => {
      const p = new URLSearchParams(q);
      p.set('level', level);
      return `/api/v1/datasets/${encodeURIComponent(d.id)}/flow?${p.toString()}`;
    };
    this.errors.clear('flow');
    this.root.dataset.state = 'loading';
    this.status.textContent = 'Tracing streamlines…';
    try {
      // Just above 1: the streamlines resampled as the bundles are, so the two blend point by point.
      const [streams, bundles] = await Promise.all([
        request<FlowJson>(url('1.000001'), { signal: ctrl.signal }),
        request<FlowJson>(url('2'), { signal: ctrl.signal }),
      ]);
      this.streams = streams, this.bundles = bundles;
      this.root.dataset.state = 'shown';
      this.root.dataset.lines = String(streams.lines.length);
      this.status.textContent = `${streams.lines.length} streamlines in ${streams.sectors} heading sectors`;
      this.apply();
    } catch (e) {
      if (isAbort(e)) return;
      this.root.dataset.state = 'failed';
      this.status.textContent = '';
      this.errors.show('flow', e instanceof ApiError ? e : new ApiError(0, { error: 'internal', detail: String(e), param: '' }));
    }
  }

  setLevel(level: number): void {
    this.level = level;
    this.value.textContent = level.toFixed(2);
    this.root.dataset.level = level.toFixed(2);
    this.apply();
  }

  private apply() {
    if (!this.streams || !this.bundles || !this.map.getSource(SOURCE)) return;
    const op = levelOpacity(this.level);
    (this.map.getSource(SOURCE) as maplibregl.GeoJSONSource).setData(toFeatures(linesAt(this.streams.lines, this.bundles.lines, this.level)));
    this.map.setPaintProperty(LAYER, 'line-opacity', op.lines);
    if (this.map.getLayer(DENSITY_LAYER)) this.map.setPaintProperty(DENSITY_LAYER, 'raster-opacity', DENSITY_OPACITY * op.density);
  }
}
