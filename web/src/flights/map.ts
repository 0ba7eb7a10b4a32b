// The map: offline basemap, the server's density tiles and the selected flight's track.

import * as maplibregl from 'maplibre-gl';
import workerUrl from 'maplibre-gl/dist/maplibre-gl-worker.mjs?url';
import 'maplibre-gl/dist/maplibre-gl.css';
import type { BBox, FlightFeature } from '../api/types';
import { ApiError, errorFromResponse } from '../api/client';
import { basemapStyle, loadBasemapData } from './basemap';
import { altitudeColorExpression, trackData } from './track';
import { h } from '../lib/dom';

maplibregl.setWorkerUrl(workerUrl);

const DENSITY = 'density';
const BUNDLE = 'bundle';
const TRACK = 'track';
const TRACK_ENDS = 'track-ends';
/** Opacity of the density and bundle rasters behind the playback view's aircraft. */
const DIMMED_OPACITY = 0.35;

export interface MapViewEvents {
  /** The view settled at new bounds (after a pan or zoom). */
  onViewChange(bbox: BBox): void;
  /** A density tile failed; the error carries the API's detail when the server sent one. */
  onTileError(err: ApiError): void;
  /** Density tiles for the current template loaded without error. */
  onTilesOk(): void;
}

export class MapView {
  readonly map: maplibregl.Map;
  private readonly container: HTMLElement;
  private readonly status: HTMLElement;
  /** Shown from a new density template until all its visible tiles have loaded (old tiles may still show). */
  private readonly loading: HTMLElement;
  private template: string | null = null;
  private bundleTemplate: string | null = null;
  private densityShown = true;
  private dimmed = false;
  private tileErrorShown = false;

  constructor(container: HTMLElement, private readonly events: MapViewEvents) {
    this.container = container;
    this.map = new maplibregl.Map({
      container,
      style: basemapStyle(),
      center: [10, 48],
      zoom: 3.2,
      minZoom: 0.5,
      maxZoom: 14,
      renderWorldCopies: false,
      attributionControl: { compact: true },
      dragRotate: false,
      pitchWithRotate: false,
      fadeDuration: 0,
    });
    this.map.touchZoomRotate.disableRotation();
    this.map.keyboard.disableRotation();
    this.map.addControl(new maplibregl.NavigationControl({ showCompass: false }), 'top-right');
    this.map.addControl(new maplibregl.ScaleControl({ unit: 'nautical' }), 'bottom-right');

    this.status = h('div', { class: 'map-status', role: 'status', 'aria-live': 'polite', hidden: true });
    this.loading = h('div', { class: 'map-loading', role: 'status', 'aria-live': 'polite', 'data-testid': 'map-loading', hidden: true }, h('span', { class: 'spinner' }), 'Loading tiles of the new view…');
    container.append(this.loading);
    const coords = h('div', { class: 'map-coords', 'aria-hidden': 'true' });
    container.append(this.status, coords);

    this.map.on('mousemove', (e) => {
      const { lng, lat } = e.lngLat;
      coords.textContent = `${Math.abs(lat).toFixed(3)}°${lat >= 0 ? 'N' : 'S'} ${Math.abs(lng).toFixed(3)}°${lng >= 0 ? 'E' : 'W'}  z${this.map.getZoom().toFixed(1)}`;
    });
    this.map.on('mouseout', () => (coords.textContent = ''));

    this.map.on('load', () => {
      this.addDataLayers();
      void loadBasemapData().then((d) => {
        (this.map.getSource('land') as maplibregl.GeoJSONSource).setData(d.land);
        (this.map.getSource('borders') as maplibregl.GeoJSONSource).setData(d.borders);
        (this.map.getSource('coast') as maplibregl.GeoJSONSource).setData(d.coast);
      });
      this.publishView();
    });
    this.map.on('moveend', () => this.publishView());

    // Idle state for the browser test and for anyone scripting the page.
    this.map.on('idle', () => {
      container.dataset.idle = 'true';
      container.dataset.densityLoaded = String(this.template !== null && this.map.isSourceLoaded(DENSITY));
      container.dataset.bundleLoaded = String(this.bundleTemplate !== null && this.map.isSourceLoaded(BUNDLE));
      container.dataset.zoom = this.map.getZoom().toFixed(3);
      container.dataset.bounds = this.bounds().join(',');
      if (this.template && !this.tileErrorShown) this.events.onTilesOk();
    });
    // The loading indicator goes once the new template's tiles are all in (or failed: the error shows).
    this.map.on('sourcedata', (e) => {
      if (e.sourceId === DENSITY && this.map.isSourceLoaded(DENSITY)) this.setLoading(false);
    });
    this.map.on('idle', () => this.setLoading(false));
    const busy = () => (container.dataset.idle = 'false');
    this.map.on('movestart', busy);
    this.map.on('dataloading', busy);

    this.map.on('error', (e) => this.handleError(e));
  }

  private addDataLayers() {
    const m = this.map;
    m.addSource(DENSITY, {
      type: 'raster',
      tiles: this.template ? [this.template] : [],
      tileSize: 256,
      minzoom: 0,
      maxzoom: 14,
    });
    m.addLayer(
      { id: DENSITY, type: 'raster', source: DENSITY, paint: { 'raster-opacity': 0.92, 'raster-fade-duration': 0 } },
      'borders',
    );

    // Bundle tiles (a bundling result of the current data set), shown instead of the density in the
    // bundling panel's "bundled" mode.
    m.addSource(BUNDLE, { type: 'raster', tiles: this.bundleTemplate ? [this.bundleTemplate] : [], tileSize: 256, minzoom: 0, maxzoom: 14 });
    m.addLayer({ id: BUNDLE, type: 'raster', source: BUNDLE, paint: { 'raster-opacity': 0.95, 'raster-fade-duration': 0 } }, 'borders');
    this.applyVisibility();

    m.addSource(TRACK, { type: 'geojson', data: { type: 'FeatureCollection', features: [] } });
    m.addSource(TRACK_ENDS, { type: 'geojson', data: { type: 'FeatureCollection', features: [] } });
    m.addLayer({
      id: 'track-casing',
      type: 'line',
      source: TRACK,
      layout: { 'line-cap': 'round', 'line-join': 'round' },
      paint: { 'line-color': '#05070a', 'line-width': 6, 'line-opacity': 0.85 },
    });
    m.addLayer({
      id: 'track-line',
      type: 'line',
      source: TRACK,
      layout: { 'line-cap': 'round', 'line-join': 'round' },
      paint: { 'line-color': altitudeColorExpression(), 'line-width': 3 },
    });
    m.addLayer({
      id: 'track-ends',
      type: 'circle',
      source: TRACK_ENDS,
      paint: {
        'circle-radius': 5,
        'circle-color': ['match', ['get', 'end'], 'start', '#3ddc84', '#f472b6'],
        'circle-stroke-color': '#05070a',
        'circle-stroke-width': 2,
      },
    });
  }

  private bounds(): BBox {
    const b = this.map.getBounds();
    return [b.getWest(), b.getSouth(), b.getEast(), b.getNorth()];
  }

  private publishView() {
    this.events.onViewChange(this.bounds());
  }

  private handleError(e: maplibregl.ErrorEvent & { sourceId?: string }) {
    if (e.sourceId !== DENSITY) {
      console.warn('map:', e.error?.message ?? e);
      return;
    }
    const err = e.error as Partial<maplibregl.AJAXError> | undefined;
    // Tiles answered for an older template are not news.
    if (!this.template || (err?.url && !sameTemplate(err.url, this.template))) return;
    if (this.tileErrorShown) return;
    this.tileErrorShown = true;
    this.setLoading(false);
    const status = err?.status ?? 0;
    const fallback = new ApiError(status, {
      error: status ? `http_${status}` : 'network',
      detail: status ? `Density tiles failed (${status} ${err?.statusText ?? ''})`.trim() : 'Density tiles could not be loaded.',
    });
    this.showStatus(fallback.detail, true);
    if (err?.body instanceof Blob) {
      void errorFromResponse(new Response(err.body, { status: status || 500, statusText: err.statusText ?? '' })).then((apiErr) =>
        this.events.onTileError(apiErr.code.startsWith('http_') ? fallback : apiErr),
      );
    } else {
      this.events.onTileError(fallback);
    }
  }

  private showStatus(text: string | null, isError = false) {
    this.status.hidden = text === null;
    this.status.textContent = text ?? '';
    this.status.classList.toggle('error', isError);
  }

  private setLoading(on: boolean) {
    if (on === !this.loading.hidden) return;
    this.loading.hidden = !on;
    this.container.dataset.loading = String(on);
  }

  /**
   * Shows density tiles for a URL template (null hides the layer). Unchanged templates do nothing. Until
   * every visible tile of the new template has loaded, the loading indicator says so: tiles of the old
   * state may still be on screen beside new ones, and the analyst must not read them as one picture.
   */
  setDensity(template: string | null): void {
    if (template === this.template) return;
    this.template = template;
    this.tileErrorShown = false;
    this.showStatus(null);
    this.setLoading(template !== null);
    this.retarget(DENSITY, template);
  }

  /** Shows a bundle's tiles (null hides them). Unchanged templates do nothing. */
  setBundleTiles(template: string | null): void {
    if (template === this.bundleTemplate) return;
    this.bundleTemplate = template;
    this.retarget(BUNDLE, template);
  }

  /**
   * Points the raster source `source` (DENSITY or BUNDLE) at a new tile template and marks it not loaded
   * (the container's data-{source}-template / -loaded, which the browser test waits on).
   */
  private retarget(source: typeof DENSITY | typeof BUNDLE, template: string | null) {
    const ds = this.container.dataset;
    ds[`${source}Template`] = template ?? '';
    ds[`${source}Loaded`] = 'false';
    ds.idle = 'false';
    const src = this.map.getSource(source) as maplibregl.RasterTileSource | undefined;
    if (!src) return; // applied in addDataLayers once the style has loaded
    if (template) src.setTiles([template]);
    this.applyVisibility();
  }

  /** Hides the density layer while a bundle is shown in its place. */
  setDensityShown(shown: boolean): void {
    this.densityShown = shown;
    this.container.dataset.densityShown = String(shown);
    this.applyVisibility();
  }

  /**
   * Dims the density and bundle layers behind the moving aircraft of the playback view (they show where
   * the window's traffic goes; the aircraft show where it is now).
   */
  setDimmed(dimmed: boolean): void {
    this.dimmed = dimmed;
    this.container.dataset.dimmed = String(dimmed);
    this.applyVisibility();
  }

  private applyVisibility() {
    if (!this.map.getLayer(DENSITY) || !this.map.getLayer(BUNDLE)) return;
    this.map.setPaintProperty(DENSITY, 'raster-opacity', this.dimmed ? DIMMED_OPACITY : 0.92);
    this.map.setPaintProperty(BUNDLE, 'raster-opacity', this.dimmed ? DIMMED_OPACITY : 0.95);
    this.map.setLayoutProperty(DENSITY, 'visibility', this.template && this.densityShown ? 'visible' : 'none');
    this.map.setLayoutProperty(BUNDLE, 'visibility', this.bundleTemplate ? 'visible' : 'none');
  }

  fitBBox(b: BBox, animate = true): void {
    const [w, s, e, n] = b;
    if (![w, s, e, n].every(Number.isFinite) || w > e || s > n) return;
    this.map.fitBounds(
      [
        [w, s],
        [e, n],
      ],
      { padding: 40, animate, maxZoom: 9 },
    );
  }

  /** Draws a flight's track (null clears it); `fit` zooms the map to it (off while the map follows a flight). */
  showTrack(f: FlightFeature | null, fit = true): void {
    const empty = { type: 'FeatureCollection' as const, features: [] };
    const trackSrc = this.map.getSource(TRACK) as maplibregl.GeoJSONSource | undefined;
    const endsSrc = this.map.getSource(TRACK_ENDS) as maplibregl.GeoJSONSource | undefined;
    if (!trackSrc || !endsSrc) return;
    if (!f) {
      trackSrc.setData(empty);
      endsSrc.setData(empty);
      delete this.container.dataset.track;
      return;
    }
    const t = trackData(f);
    trackSrc.setData(t.segments);
    endsSrc.setData(t.ends);
    this.container.dataset.track = String(f.properties.id);
    if (t.bounds && fit) {
      const [w, s, e, n] = t.bounds;
      this.map.fitBounds(
        [
          [w, s],
          [e, n],
        ],
        { padding: { top: 80, bottom: 60, left: 60, right: 60 }, maxZoom: 10, duration: 600 },
      );
    }
  }
}

/** Whether a tile URL was made from a template (same path prefix and query). */
function sameTemplate(url: string, template: string): boolean {
  const [tPath, tQuery] = template.split('?');
  const [uPath, uQuery] = url.split('?');
  const prefix = tPath!.slice(0, tPath!.indexOf('{z}'));
  return (uPath ?? '').startsWith(prefix) && (uQuery ?? '') === (tQuery ?? '');
}
