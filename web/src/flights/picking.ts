// Hover and click on the density map: the flights whose trails the tiles draw nearest the cursor
// (GET /api/v1/datasets/{id}/pick with the tiles' window and filters, the map's zoom and 512-px tiles, as
// MapLibre measures zoom). Hover shows the nearest in a tooltip; a click selects it. Off while the playback
// view (which picks its own moving aircraft) or a bundle is shown.

import type * as maplibregl from 'maplibre-gl';
import { request, isAbort } from '../api/client';
import { h } from '../lib/dom';
import { formatFlightLevel, formatUtcSeconds } from '../lib/format';

/** A flight near the cursor, as the pick route answers. */
export interface PickedFlight {
  id: number;
  icao24: string;
  callsign: string;
  distance_px: number;
  t: number;
  lon: number;
  lat: number;
  alt_m: number | null;
}

export interface PickAnswer {
  flights: PickedFlight[];
  zoom: number;
  tile_size: number;
  tolerance_px: number;
}

/** Screen pixels around the cursor within which a trail counts as under it. */
export const PICK_TOLERANCE_PX = 5;
const HOVER_DELAY_MS = 60;

/** The pick request's query: the tiles' filters plus the point, the zoom and MapLibre's 512-px tiles. */
export function pickQuery(filters: URLSearchParams, lng: number, lat: number, zoom: number, limit = 5): URLSearchParams {
  const q = new URLSearchParams(filters);
  q.set('lon', lng.toFixed(6));
  q.set('lat', lat.toFixed(6));
  q.set('zoom', zoom.toFixed(4));
  q.set('tile_size', '512');
  q.set('tolerance', String(PICK_TOLERANCE_PX));
  q.set('limit', String(limit));
  return q;
}

export interface PickingDeps {
  map: maplibregl.Map;
  /** The data set and the tiles' query (null: nothing to pick). */
  target(): { dataset: string; query: URLSearchParams } | null;
  /** Whether picking applies now (density shown, playback off). */
  enabled(): boolean;
  onSelect(f: PickedFlight): void;
}

export class Picking {
  private readonly tip: HTMLElement;
  /** Hover and click are separate channels: the move a click makes must not cancel the click's question. */
  private readonly ctrls: Record<'hover' | 'click', AbortController | null> = { hover: null, click: null };
  private timer = 0;
  private last: PickedFlight[] = [];

  constructor(container: HTMLElement, private readonly deps: PickingDeps) {
    this.tip = h('div', { class: 'pick-tip', 'data-testid': 'pick-tooltip', hidden: true, role: 'status' });
    container.append(this.tip);
    const m = deps.map;
    m.on('mousemove', (e) => this.schedule(e.lngLat, e.point));
    m.on('mouseout', () => this.hide());
    m.on('movestart', () => this.hide());
    m.on('click', (e) => void this.click(e.lngLat));
  }

  private schedule(ll: maplibregl.LngLat, pt: maplibregl.Point) {
    window.clearTimeout(this.timer);
    if (!this.deps.enabled()) return this.hide();
    this.timer = window.setTimeout(() => void this.hover(ll, pt), HOVER_DELAY_MS);
  }

  /** Asks the API; a newer question of the same kind (hover or click) cancels the older one. */
  private async ask(ll: maplibregl.LngLat, limit: number, kind: 'hover' | 'click'): Promise<PickAnswer | null> {
    const t = this.deps.target();
    if (!t) return null;
    this.ctrls[kind]?.abort();
    const ctrl = new AbortController();
    this.ctrls[kind] = ctrl;
    const q = pickQuery(t.query, ll.lng, ll.lat, this.deps.map.getZoom(), limit);
    try {
      return await request<PickAnswer>(`/api/v1/datasets/${encodeURIComponent(t.dataset)}/pick?${q.toString()}`, { signal: ctrl.signal });
    } catch (e) {
      if (!isAbort(e)) console.warn('pick:', e);
      return null;
    }
  }

  private async hover(ll: maplibregl.LngLat, pt: maplibregl.Point) {
    const a = await this.ask(ll, 5, 'hover');
    if (!a || !this.deps.enabled()) return;
    this.last = a.flights;
    const c = this.deps.map.getCanvas().parentElement!;
    c.dataset.hoverFlight = a.flights[0] ? String(a.flights[0].id) : '';
    if (a.flights.length === 0) return this.hide();
    const f = a.flights[0]!;
    this.tip.replaceChildren(
      h('b', { class: 'mono' }, f.callsign || '—'),
      ` ${f.icao24 || ''} · ${formatFlightLevel(f.alt_m)} · ${formatUtcSeconds(f.t).slice(11)} UTC`,
      a.flights.length > 1 ? h('span', { class: 'muted' }, ` · +${a.flights.length - 1} more`) : '',
    );
    this.tip.dataset.flightId = String(f.id);
    this.tip.dataset.flights = a.flights.map((x) => x.id).join(',');
    this.tip.hidden = false;
    this.tip.style.left = `${pt.x + 14}px`;
    this.tip.style.top = `${pt.y + 14}px`;
  }

  private async click(ll: maplibregl.LngLat) {
    if (!this.deps.enabled()) return;
    const a = await this.ask(ll, 1, 'click');
    const f = a?.flights[0];
    if (f) this.deps.onSelect(f);
  }

  private hide() {
    window.clearTimeout(this.timer);
    this.tip.hidden = true;
  }

  /** The flights of the last hover (nearest first). */
  get hovered(): readonly PickedFlight[] {
    return this.last;
  }
}
