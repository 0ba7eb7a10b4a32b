// Builds the query string shared by summary, flights and density tiles, and parses it back
// (the URL hash keeps the same parameters so a view can be shared).

import type { BBox, Colormap, DensityHow, DensityValue } from './types';

export type OnGround = 'any' | 'true' | 'false';

/** The analyst's filters. `null` / '' means "not filtered". Altitudes are in feet. */
export interface Filters {
  t0: number | null;
  t1: number | null;
  altMin: number | null;
  altMax: number | null;
  callsign: string;
  icao24: string;
  onGround: OnGround;
  bbox: BBox | null;
}

export interface RenderOptions {
  value: DensityValue;
  how: DensityHow;
  cmap: Colormap;
}

export const EMPTY_FILTERS: Readonly<Filters> = Object.freeze({
  t0: null,
  t1: null,
  altMin: null,
  altMax: null,
  callsign: '',
  icao24: '',
  onGround: 'any',
  bbox: null,
});

export const DEFAULT_RENDER: Readonly<RenderOptions> = Object.freeze({
  value: 'count',
  how: 'eq_hist',
  cmap: 'fire',
});

export const DENSITY_VALUES: readonly DensityValue[] = ['count', 'altitude', 'speed'];
export const DENSITY_HOWS: readonly DensityHow[] = ['linear', 'log', 'eq_hist'];
export const COLORMAPS: readonly Colormap[] = ['fire', 'viridis', 'inferno', 'magma', 'gray'];

const LAT_LIMIT = 85.0511;

/** Clamps a map view to valid WGS84 degrees and rounds it to 1e-4° (about 10 m) so URLs stay short and stable. */
export function normalizeBBox(b: BBox): BBox {
  const r = (v: number) => Math.round(v * 1e4) / 1e4;
  const clamp = (v: number, lo: number, hi: number) => Math.min(hi, Math.max(lo, v));
  const west = clamp(b[0], -180, 180);
  const east = clamp(b[2], -180, 180);
  const south = clamp(b[1], -LAT_LIMIT, LAT_LIMIT);
  const north = clamp(b[3], -LAT_LIMIT, LAT_LIMIT);
  return [r(west), r(Math.min(south, north)), r(east), r(Math.max(south, north))];
}

/** "aal*, baw " → "AAL*,BAW": callsigns are upper case on the wire; a list is comma separated. */
export function normalizeCallsign(s: string): string {
  return s
    .split(/[\s,]+/)
    .filter(Boolean)
    .map((c) => c.toUpperCase())
    .join(',');
}

/** "A1B2C3 4ca7b5" → "a1b2c3,4ca7b5": ICAO 24-bit addresses are lower-case hex, deduplicated. */
export function normalizeIcao24(s: string): string {
  const seen = new Set<string>();
  for (const part of s.split(/[\s,;]+/)) {
    const v = part.trim().toLowerCase();
    if (v) seen.add(v);
  }
  return [...seen].join(',');
}

export interface QueryOptions {
  /** Leave the time window out (for the brush's histogram, which always spans the whole data set). */
  withoutTime?: boolean;
  /** Leave the bbox out (density tiles: the view box would only re-key every tile on each pan). */
  withoutBBox?: boolean;
}

/**
 * The canonical query string for a filter set, parameters always in the same order so that equal
 * filters give equal URLs (and the server's tile cache and ETags hit).
 */
export function buildQuery(f: Filters, opts: QueryOptions = {}): URLSearchParams {
  const q = new URLSearchParams();
  if (f.bbox && !opts.withoutBBox) q.set('bbox', normalizeBBox(f.bbox).join(','));
  if (!opts.withoutTime) {
    if (f.t0 !== null) q.set('t0', String(Math.floor(f.t0)));
    if (f.t1 !== null) q.set('t1', String(Math.ceil(f.t1)));
  }
  if (f.altMin !== null) q.set('alt_min', String(f.altMin));
  if (f.altMax !== null) q.set('alt_max', String(f.altMax));
  if (f.altMin !== null || f.altMax !== null) q.set('alt_unit', 'ft');
  const icao = normalizeIcao24(f.icao24);
  if (icao) q.set('icao24', icao);
  const cs = normalizeCallsign(f.callsign);
  if (cs) q.set('callsign', cs);
  if (f.onGround !== 'any') q.set('on_ground', f.onGround);
  return q;
}

/** `/tiles/{dataset}/density/{z}/{x}/{y}.png?...` as an absolute URL template for MapLibre. */
export function densityTileTemplate(origin: string, dataset: string, query: URLSearchParams, r: RenderOptions): string {
  const q = new URLSearchParams(query);
  q.set('value', r.value);
  q.set('how', r.how);
  q.set('cmap', r.cmap);
  q.set('size', '256');
  return `${origin}/tiles/${encodeURIComponent(dataset)}/density/{z}/{x}/{y}.png?${q.toString()}`;
}

function num(v: string | null): number | null {
  if (v === null || v.trim() === '') return null;
  const n = Number(v);
  return Number.isFinite(n) ? n : null;
}

function pick<T extends string>(v: string | null, allowed: readonly T[], fallback: T): T {
  return v !== null && (allowed as readonly string[]).includes(v) ? (v as T) : fallback;
}

/** Reads filters back from a query string (inverse of buildQuery for the values it writes; alt_unit=m is converted to ft). */
export function parseFilters(q: URLSearchParams): Filters {
  const f: Filters = { ...EMPTY_FILTERS };
  const bbox = q.get('bbox')?.split(',').map(Number);
  if (bbox && bbox.length === 4 && bbox.every(Number.isFinite)) f.bbox = bbox as BBox;
  f.t0 = num(q.get('t0'));
  f.t1 = num(q.get('t1'));
  const toFt = q.get('alt_unit') === 'm' ? 1 / 0.3048 : 1;
  const amin = num(q.get('alt_min'));
  const amax = num(q.get('alt_max'));
  f.altMin = amin === null ? null : Math.round(amin * toFt);
  f.altMax = amax === null ? null : Math.round(amax * toFt);
  f.callsign = q.get('callsign') ?? '';
  f.icao24 = q.get('icao24') ?? '';
  f.onGround = pick<OnGround>(q.get('on_ground'), ['true', 'false'], 'any');
  return f;
}

export function parseRender(q: URLSearchParams): RenderOptions {
  return {
    value: pick(q.get('value'), DENSITY_VALUES, DEFAULT_RENDER.value),
    how: pick(q.get('how'), DENSITY_HOWS, DEFAULT_RENDER.how),
    cmap: pick(q.get('cmap'), COLORMAPS, DEFAULT_RENDER.cmap),
  };
}

const KNOWN_EXTENSIONS = /\.(gz|gzip|zst|so6|json|jsonl|csv|txt|trace|readsb)$/i;

/**
 * A data set id from an uploaded file's name: the server accepts 1–64 of [a-z0-9_-].
 * "traffic_europe_20180101_m3.so6.gz" → "traffic_europe_20180101_m3".
 */
export function datasetNameFromFile(fileName: string): string {
  let base = fileName.replace(/^.*[\\/]/, '');
  while (KNOWN_EXTENSIONS.test(base)) base = base.replace(KNOWN_EXTENSIONS, '');
  const id = base
    .toLowerCase()
    .replace(/[^a-z0-9_-]+/g, '-')
    .replace(/-{2,}/g, '-')
    .replace(/^-+|-+$/g, '')
    .slice(0, 64)
    .replace(/-+$/, '');
  return id || 'dataset';
}

/** The server's longest callsign pattern (limits::kMaxCallsignPatternLength). */
export const CALLSIGN_PATTERN_MAX = 16;

/** A filter problem found before asking the server, in the API's error shape. */
export interface FilterProblem {
  param: string;
  detail: string;
}

/**
 * Checks what the client can know for certain, so that an obviously invalid query is not sent
 * (the server stays the authority; anything it rejects is shown the same way).
 */
export function validateFilters(f: Filters): FilterProblem | null {
  if (f.t0 !== null && f.t1 !== null && f.t0 >= f.t1) return { param: 't0', detail: 'The time window ends before it starts.' };
  if (f.altMin !== null && f.altMax !== null && f.altMin > f.altMax)
    return { param: 'alt_min', detail: `The band's lower altitude (${f.altMin} ft) is above its upper one (${f.altMax} ft).` };
  const cs = normalizeCallsign(f.callsign);
  if (cs.length > CALLSIGN_PATTERN_MAX)
    return { param: 'callsign', detail: `A callsign pattern has at most ${CALLSIGN_PATTERN_MAX} characters (this one has ${cs.length}).` };
  if (cs && !/^[A-Z0-9*?]+$/.test(cs))
    return { param: 'callsign', detail: `One callsign pattern of letters, digits, * and ? (not "${cs}"), e.g. AFR* or BAW1?.` };
  const bad = normalizeIcao24(f.icao24)
    .split(',')
    .filter((a) => a && !/^[0-9a-f]{6}$/.test(a));
  if (bad.length > 0) return { param: 'icao24', detail: `Not a 24-bit hex address: ${bad.slice(0, 3).join(', ')} (six hex digits, e.g. 4ca7b5).` };
  return null;
}
