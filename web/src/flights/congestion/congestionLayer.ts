// The congestion panel's map layers: the volumes' footprints coloured by their class at the current
// instant (feature state, so a new instant costs no re-tiling), the selected volume's outline, the
// involved flights of a hotspot, and the separation events as markers at their closest point of approach.

import type * as maplibregl from 'maplibre-gl';
import type { FeatureCollection, LineString, Polygon } from 'geojson';
import { CLASS_STYLE, cpaPoint, type Footprint, type OccClass } from './model';
import type { SeparationEvent } from './types';

const VOL = 'cong-volumes';
const VOL_FILL = 'cong-volumes-fill';
const VOL_LINE = 'cong-volumes-line';
const FLIGHTS = 'cong-flights';
const SEP = 'cong-separation';
const TILES = 'cong-map-tiles';
const EMPTY: FeatureCollection = { type: 'FeatureCollection', features: [] };


export interface CongestionLayerEvents {
  onVolumeClick(footprint: string): void;
  onEventClick(index: number): void;
  /** A congestion-map tile failed (once per template): the status line, or the API's detail. */
  onTilesError(detail: string): void;
}

export class CongestionLayer {
  private readonly keys: string[] = [];
  private readonly index = new Map<string, number>();
  private shown = new Map<number, OccClass>();
  private selected: number | null = null;
  private active = new Set<number>();
  private ready = false;
  private tileTemplate: string | null = null;
  private tileErrorShown = false;
  private pending: (() => void)[] = [];

  constructor(
    private readonly map: maplibregl.Map,
    private readonly events: CongestionLayerEvents,
  ) {
    if (map.getLayer('track-casing')) this.add();
    else map.once('load', () => this.add());
  }

  private add() {
    const m = this.map;
    const before = m.getLayer('track-casing') ? 'track-casing' : undefined;
    // The congestion map (thresholded aircraft per pixel) under the volumes.
    m.addSource(TILES, { type: 'raster', tiles: this.tileTemplate ? [this.tileTemplate] : [], tileSize: 256 });
    m.addLayer({ id: TILES, type: 'raster', source: TILES, layout: { visibility: this.tileTemplate ? 'visible' : 'none' }, paint: { 'raster-opacity': 0.85, 'raster-fade-duration': 0 } }, before);
    m.addSource(VOL, { type: 'geojson', data: EMPTY });
    m.addSource(FLIGHTS, { type: 'geojson', data: EMPTY });
    m.addSource(SEP, { type: 'geojson', data: EMPTY });
    const cls: maplibregl.ExpressionSpecification = ['to-string', ['feature-state', 'cls']];
    const colors: (string | maplibregl.ExpressionSpecification)[] = [];
    for (const s of CLASS_STYLE) colors.push(s.cls, s.color);
    m.addLayer(
      {
        id: VOL_FILL,
        type: 'fill',
        source: VOL,
        paint: {
          'fill-color': ['match', cls, ...colors, 'rgba(0,0,0,0)'] as unknown as maplibregl.ExpressionSpecification,
          'fill-opacity': ['match', cls, 'peak', 0.7, 'sustained', 0.6, 'near', 0.45, 'low', 0.2, 'count', 0.2, 0],
        },
      },
      before,
    );
    m.addLayer(
      {
        id: VOL_LINE,
        type: 'line',
        source: VOL,
        paint: {
          'line-color': ['case', ['boolean', ['feature-state', 'selected'], false], '#ffffff', '#8a97a8'],
          'line-width': ['case', ['boolean', ['feature-state', 'selected'], false], 2.5, 0.8],
          'line-opacity': ['case', ['boolean', ['feature-state', 'selected'], false], 1, ['==', ['get', 'sector'], true], 0.6, 0],
        },
      },
      before,
    );
    m.addLayer(
      {
        id: FLIGHTS,
        type: 'line',
        source: FLIGHTS,
        layout: { 'line-cap': 'round', 'line-join': 'round' },
        paint: { 'line-color': '#5ee7ff', 'line-width': 2, 'line-opacity': 0.9 },
      },
      before,
    );
    m.addLayer({
      id: SEP,
      type: 'circle',
      source: SEP,
      paint: {
        'circle-radius': ['case', ['boolean', ['feature-state', 'active'], false], 8, 4.5],
        'circle-color': ['case', ['boolean', ['feature-state', 'active'], false], '#ff3df2', '#b27cff'],
        'circle-stroke-color': '#05070a',
        'circle-stroke-width': 1.5,
      },
    });
    m.on('click', VOL_FILL, (e) => {
      const id = e.features?.[0]?.id;
      if (typeof id === 'number' && this.keys[id] !== undefined) this.events.onVolumeClick(this.keys[id]!);
    });
    m.on('click', SEP, (e) => {
      const id = e.features?.[0]?.id;
      if (typeof id === 'number') this.events.onEventClick(id);
    });
    for (const l of [VOL_FILL, SEP]) {
      m.on('mouseenter', l, () => (m.getCanvas().style.cursor = 'pointer'));
      m.on('mouseleave', l, () => (m.getCanvas().style.cursor = ''));
    }
    m.on('error', (e: maplibregl.ErrorEvent & { sourceId?: string }) => {
      if (e.sourceId !== TILES || this.tileErrorShown || !this.tileTemplate) return;
      this.tileErrorShown = true;
      const err = e.error as { status?: number; body?: unknown } | undefined;
      const status = err?.status ?? 0;
      const fallback = status ? `tiles failed (${status})` : 'tiles could not be loaded';
      if (err?.body instanceof Blob) {
        void err.body
          .text()
          .then((t) => (JSON.parse(t) as { detail?: string }).detail ?? fallback)
          .catch(() => fallback)
          .then((d) => this.events.onTilesError(d));
      } else this.events.onTilesError(fallback);
    });
    this.ready = true;
    for (const f of this.pending.splice(0)) f();
  }

  private whenReady(f: () => void) {
    if (this.ready) f();
    else this.pending.push(f);
  }

  congestionTiles(): string | null {
    return this.tileTemplate;
  }

  /** The congestion map's tile template (null hides it); an unchanged template does nothing. */
  setCongestionTiles(template: string | null): void {
    if (template === this.tileTemplate) return;
    this.tileTemplate = template;
    this.tileErrorShown = false;
    this.map.getContainer().dataset.congestionTiles = template ?? '';
    this.whenReady(() => {
      if (template) (this.map.getSource(TILES) as maplibregl.RasterTileSource).setTiles([template]);
      this.map.setLayoutProperty(TILES, 'visibility', template ? 'visible' : 'none');
    });
  }

  /** The footprints of a result (null clears everything). */
  setFootprints(fps: Footprint[] | null): void {
    this.keys.length = 0;
    this.index.clear();
    this.shown = new Map();
    this.selected = null;
    const fc: FeatureCollection<Polygon> = { type: 'FeatureCollection', features: [] };
    for (const fp of fps ?? []) {
      const id = this.keys.length;
      this.keys.push(fp.key);
      this.index.set(fp.key, id);
      fc.features.push({ type: 'Feature', id, properties: { key: fp.key, sector: fp.sector }, geometry: { type: 'Polygon', coordinates: [fp.ring] } });
    }
    this.whenReady(() => {
      this.map.removeFeatureState({ source: VOL });
      (this.map.getSource(VOL) as maplibregl.GeoJSONSource).setData(fc);
    });
  }

  /** Each footprint's class now (footprints absent from `states` are empty). */
  setStates(states: Map<string, { cls: OccClass }>): void {
    const next = new Map<number, OccClass>();
    for (const [key, s] of states) {
      const id = this.index.get(key);
      if (id !== undefined) next.set(id, s.cls);
    }
    const prev = this.shown;
    this.shown = next;
    this.whenReady(() => {
      for (const [id, c] of next) if (prev.get(id) !== c) this.map.setFeatureState({ source: VOL, id }, { cls: c });
      for (const id of prev.keys()) if (!next.has(id)) this.map.setFeatureState({ source: VOL, id }, { cls: 'empty' });
    });
  }

  setSelected(key: string | null): void {
    const id = key === null ? null : (this.index.get(key) ?? null);
    const prev = this.selected;
    this.selected = id;
    this.whenReady(() => {
      if (prev !== null) this.map.setFeatureState({ source: VOL, id: prev }, { selected: false });
      if (id !== null) this.map.setFeatureState({ source: VOL, id }, { selected: true });
    });
  }

  /** The involved flights' tracks (each a list of [lon, lat]). */
  setFlights(lines: { id: number; coords: [number, number][] }[]): void {
    const fc: FeatureCollection<LineString> = {
      type: 'FeatureCollection',
      features: lines.filter((l) => l.coords.length >= 2).map((l) => ({ type: 'Feature', id: l.id, properties: {}, geometry: { type: 'LineString', coordinates: l.coords } })),
    };
    this.whenReady(() => (this.map.getSource(FLIGHTS) as maplibregl.GeoJSONSource).setData(fc));
  }

  /** Separation events as markers at the middle of the two aircraft at the closest point of approach. */
  setEvents(events: readonly SeparationEvent[] | null): void {
    this.active = new Set();
    const fc: FeatureCollection = {
      type: 'FeatureCollection',
      features: (events ?? []).map((e, i) => ({ type: 'Feature', id: i, properties: {}, geometry: { type: 'Point', coordinates: cpaPoint(e) } })),
    };
    this.whenReady(() => {
      this.map.removeFeatureState({ source: SEP });
      (this.map.getSource(SEP) as maplibregl.GeoJSONSource).setData(fc);
    });
  }

  /** The events in progress now (indices into the list given to setEvents). */
  setActiveEvents(ids: Set<number>): void {
    const prev = this.active;
    this.active = ids;
    this.whenReady(() => {
      for (const id of prev) if (!ids.has(id)) this.map.setFeatureState({ source: SEP, id }, { active: false });
      for (const id of ids) if (!prev.has(id)) this.map.setFeatureState({ source: SEP, id }, { active: true });
    });
  }
}
