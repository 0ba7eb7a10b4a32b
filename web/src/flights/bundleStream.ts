// Bundles that follow the clock: a WebSocket to /api/v1/datasets/{id}/bundles/stream (proto/bundle_stream.md).
// The caller's clock is sent as control messages (throttled), each TSBS frame the server sends is decoded
// and drawn as one MapLibre line layer with a per-trail opacity (the server's fade), placed under the
// other data layers so that moving aircraft and tracks stay on top.

import type * as maplibregl from 'maplibre-gl';
import { ReconnectingSocket } from '../api/socket';

export const TSBS_MAGIC = 'TSBS';
export const TSBS_VERSION = 1;
const HEADER_BYTES = 40;

/** One decoded update. The arrays are views on the frame's buffer (no copy). */
export interface TsbsFrame {
  /** The clock of this update, Unix seconds. */
  t: number;
  sequence: number;
  windowS: number;
  /** Mean drift of the persistent trails in this update, px of the server's 512-px frame. */
  driftPx: number;
  n: number;
  m: number;
  /** Per trail, the flight id (its index in the dataset). */
  ids: Uint32Array;
  /** Per trail, its opacity (0, 1]. */
  opacity: Float32Array;
  /** n + 1 entries: trail i is points offsets[i] .. offsets[i+1]-1. */
  offsets: Uint32Array;
  /** lon, lat degrees interleaved, 2m values. */
  points: Float32Array;
}

export class TsbsError extends Error {
  constructor(message: string) {
    super(`TSBS: ${message}`);
    this.name = 'TsbsError';
  }
}

/** Decodes a TSBS frame; throws TsbsError when it is malformed (wrong magic or version, sizes that disagree). */
export function decodeTsbs(buf: ArrayBuffer): TsbsFrame {
  if (buf.byteLength < HEADER_BYTES + 4) throw new TsbsError(`${buf.byteLength} bytes is shorter than the header`);
  const dv = new DataView(buf);
  const magic = String.fromCharCode(dv.getUint8(0), dv.getUint8(1), dv.getUint8(2), dv.getUint8(3));
  if (magic !== TSBS_MAGIC) throw new TsbsError(`bad magic "${magic}"`);
  const version = dv.getUint32(4, true);
  if (version !== TSBS_VERSION) throw new TsbsError(`version ${version} is not ${TSBS_VERSION}`);
  const n = dv.getUint32(8, true);
  const m = dv.getUint32(12, true);
  const want = HEADER_BYTES + 4 + 12 * n + 8 * m;
  if (buf.byteLength !== want) throw new TsbsError(`${buf.byteLength} bytes, expected ${want} for ${n} trails and ${m} points`);
  const ids = new Uint32Array(buf, HEADER_BYTES, n);
  const opacity = new Float32Array(buf, HEADER_BYTES + 4 * n, n);
  const offsets = new Uint32Array(buf, HEADER_BYTES + 8 * n, n + 1);
  if (offsets[0] !== 0 || offsets[n] !== m) throw new TsbsError('offsets do not span the points');
  for (let i = 0; i < n; i++) if (offsets[i + 1] < offsets[i]) throw new TsbsError(`offsets decrease at trail ${i}`);
  return {
    t: dv.getFloat64(16, true),
    sequence: dv.getUint32(24, true),
    windowS: dv.getFloat32(28, true),
    driftPx: dv.getFloat32(32, true),
    n,
    m,
    ids,
    opacity,
    offsets,
    points: new Float32Array(buf, HEADER_BYTES + 4 + 12 * n, 2 * m),
  };
}

/** The frame as GeoJSON lines, each with its flight id and opacity (properties `id`, `o`). */
export function frameToGeoJson(f: TsbsFrame): GeoJSON.FeatureCollection<GeoJSON.LineString> {
  const features: GeoJSON.Feature<GeoJSON.LineString>[] = new Array(f.n);
  for (let i = 0; i < f.n; i++) {
    const coords: number[][] = [];
    for (let k = f.offsets[i]; k < f.offsets[i + 1]; k++) coords.push([f.points[2 * k], f.points[2 * k + 1]]);
    features[i] = { type: 'Feature', properties: { id: f.ids[i], o: f.opacity[i] }, geometry: { type: 'LineString', coordinates: coords } };
  }
  return { type: 'FeatureCollection', features };
}

/** A control message of the stream (proto/bundle_stream.md). */
export interface StreamControl {
  t?: number;
  window_s?: number;
  fade_s?: number;
  bbox?: string | null;
  callsign?: string;
  icao24?: string;
}

/**
 * Sends the clock at most every `intervalMs`: the first change goes out at once, later ones within the
 * interval are coalesced into the newest, sent when it ends. `now` is injectable for tests.
 */
export class ClockThrottle {
  private lastSent = -Infinity;
  private pending: number | null = null;
  private timer: ReturnType<typeof setTimeout> | undefined;

  constructor(
    private readonly intervalMs: number,
    private readonly send: (t: number) => void,
    private readonly now: () => number = () => performance.now(),
  ) {}

  push(t: number): void {
    const at = this.now();
    if (at - this.lastSent >= this.intervalMs && this.timer === undefined) {
      this.lastSent = at;
      this.send(t);
      return;
    }
    this.pending = t;
    if (this.timer === undefined)
      this.timer = setTimeout(() => {
        this.timer = undefined;
        if (this.pending === null) return;
        const p = this.pending;
        this.pending = null;
        this.lastSent = this.now();
        this.send(p);
      }, Math.max(0, this.intervalMs - (at - this.lastSent)));
  }

  cancel(): void {
    clearTimeout(this.timer);
    this.timer = undefined;
    this.pending = null;
  }
}

export interface BundleStreamOptions {
  /** W, seconds (default 3600). */
  windowS?: number;
  /** Fade ramp, seconds (default: the server's, 300, clamped to W). */
  fadeS?: number;
  /** Follow the map's view: the stream's frame is the visible bbox, re-sent after each move (default true). */
  followView?: boolean;
  callsign?: string;
  icao24?: string;
  /** How often the clock is sampled, ms (default 100: the server's update rate). */
  intervalMs?: number;
  /** The layer goes under this layer (default: above the basemap and the raster density, under every other layer). */
  beforeId?: string;
  color?: string;
  width?: number;
  /** Called with each decoded frame (e.g. for a status line or tests). */
  onFrame?: (f: TsbsFrame) => void;
  /** Called with the server's error messages ({error, param, detail}). */
  onError?: (e: { error: string; param: string; detail: string }) => void;
}

export interface BundleStreamHandle {
  stop(): void;
  setWindow(seconds: number): void;
}

const LAYER = 'bundle-stream';
const SOURCE = 'bundle-stream';
// The basemap's vector layers (basemap.ts) and the raster data layers (density, bundle tiles; map.ts) stay
// below the stream; the first other layer (tracks, aircraft) goes above it.
const BASEMAP_LAYERS = new Set(['background', 'land', 'borders', 'coast']);

function defaultBeforeId(map: maplibregl.Map): string | undefined {
  const layers = map.getStyle()?.layers ?? [];
  for (const l of layers)
    if (!BASEMAP_LAYERS.has(l.id) && l.type !== 'background' && l.type !== 'raster' && l.id !== LAYER) return l.id;
  return undefined;
}

function viewBbox(map: maplibregl.Map): string {
  const b = map.getBounds();
  const clampLat = (v: number) => Math.max(-85, Math.min(85, v));
  let w = b.getWest(), e = b.getEast();
  if (e - w >= 360) (w = -180), (e = 180);
  const wrap = (v: number) => ((((v + 180) % 360) + 360) % 360) - 180;
  return `${wrap(w).toFixed(5)},${clampLat(b.getSouth()).toFixed(5)},${(e - w >= 360 ? 180 : wrap(e)).toFixed(5)},${clampLat(b.getNorth()).toFixed(5)}`;
}

/**
 * Opens the bundle stream of `datasetId` and draws it on `map` until stop(). `getTime()` is the playback
 * clock in Unix seconds, sampled every `intervalMs` and sent when it changes.
 */
export function startBundleStream(
  map: maplibregl.Map,
  datasetId: string,
  getTime: () => number,
  options: BundleStreamOptions = {},
): BundleStreamHandle {
  const interval = options.intervalMs ?? 100;
  const followView = options.followView ?? true;
  let windowS = options.windowS ?? 3600;
  let lastT: number | null = null;
  let stopped = false;

  const ensureLayer = () => {
    if (map.getSource(SOURCE)) return;
    map.addSource(SOURCE, { type: 'geojson', data: { type: 'FeatureCollection', features: [] } });
    map.addLayer(
      {
        id: LAYER,
        type: 'line',
        source: SOURCE,
        layout: { 'line-cap': 'round', 'line-join': 'round' },
        paint: {
          'line-color': options.color ?? '#ffc457',
          'line-width': options.width ?? 1.2,
          'line-opacity': ['*', 0.35, ['get', 'o']],
        },
      },
      options.beforeId ?? defaultBeforeId(map),
    );
  };

  const full = (): StreamControl => {
    const c: StreamControl = { window_s: windowS };
    if (options.fadeS !== undefined) c.fade_s = Math.min(options.fadeS, windowS);
    c.bbox = followView ? viewBbox(map) : null;
    if (options.callsign) c.callsign = options.callsign;
    if (options.icao24) c.icao24 = options.icao24;
    if (lastT !== null) c.t = lastT;
    return c;
  };

  const socket = new ReconnectingSocket(`/api/v1/datasets/${encodeURIComponent(datasetId)}/bundles/stream`, {
    onState: (s) => {
      if (s === 'open') socket.send(JSON.stringify(full())); // a new connection starts from the current state
    },
    onText: (text) => {
      const j = JSON.parse(text) as { type?: string; error?: string; param?: string; detail?: string };
      if (j.type === 'error') options.onError?.({ error: j.error ?? '', param: j.param ?? '', detail: j.detail ?? '' });
    },
    onBinary: (data) => {
      if (stopped) return;
      let f: TsbsFrame;
      try {
        f = decodeTsbs(data);
      } catch (e) {
        options.onError?.({ error: 'decode', param: 'frame', detail: (e as Error).message });
        return;
      }
      if (map.isStyleLoaded()) {
        ensureLayer();
        (map.getSource(SOURCE) as maplibregl.GeoJSONSource).setData(frameToGeoJson(f));
      }
      options.onFrame?.(f);
    },
    // 404 (no such dataset) and 409 (too many streams) refuse the upgrade; the browser reports 1006.
    isFinal: (ev) => ev.code === 1008,
  });

  const throttle = new ClockThrottle(interval, (t) => socket.send(JSON.stringify({ t })));
  const tick = window.setInterval(() => {
    const t = getTime();
    if (!Number.isFinite(t) || t === lastT) return;
    lastT = t;
    throttle.push(t);
  }, interval);
  const onMoveEnd = () => socket.send(JSON.stringify({ bbox: viewBbox(map) }));
  if (followView) map.on('moveend', onMoveEnd);
  socket.start();

  return {
    stop() {
      stopped = true;
      window.clearInterval(tick);
      throttle.cancel();
      if (followView) map.off('moveend', onMoveEnd);
      socket.stop();
      if (map.getLayer(LAYER)) map.removeLayer(LAYER);
      if (map.getSource(SOURCE)) map.removeSource(SOURCE);
    },
    setWindow(seconds: number) {
      windowS = seconds;
      socket.send(JSON.stringify({ window_s: seconds }));
    },
  };
}
