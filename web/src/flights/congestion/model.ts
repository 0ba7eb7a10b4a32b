// The congestion panel's pure logic (no DOM, no map): a result of GET /api/v1/congestion/{job} as a model
// with dense look-ups, the counting period at an instant, the periods of a time window, the colour class
// of an occupancy against its thresholds, the ranking of hotspots, and the CSV tables parsed back.
// The definitions of the counts are in compute/include/trailscope/congestion/counts.hpp.

import type { FeatureCollection } from 'geojson';
import type { CongestionResultWire, HotspotKind, SeparationEvent, WireHotspot, WireSeries, WireVolume } from './types';

// ---------- sparse series ----------

/** A sparse series: ascending indices with a non-zero value; every other index is 0. */
export class SparseSeries {
  constructor(
    readonly index: Uint32Array,
    readonly value: Uint32Array,
  ) {}

  static fromWire(s: WireSeries | undefined, what: string): SparseSeries {
    const idx = s?.step ?? s?.window ?? [];
    const cnt = s?.count ?? [];
    if (!Array.isArray(idx) || !Array.isArray(cnt) || idx.length !== cnt.length) throw new Error(`${what}: indices and counts differ in length`);
    for (let i = 1; i < idx.length; i++) if (!(idx[i]! > idx[i - 1]!)) throw new Error(`${what}: indices not ascending at ${i}`);
    return new SparseSeries(Uint32Array.from(idx), Uint32Array.from(cnt));
  }

  /** The value at index k (0 where absent). */
  at(k: number): number {
    const i = lowerBound(this.index, k);
    return i < this.index.length && this.index[i] === k ? this.value[i]! : 0;
  }

  /** The largest value over indices [k0, k1] (inclusive); 0 when none is stored there. */
  maxIn(k0: number, k1: number): number {
    let m = 0;
    for (let i = lowerBound(this.index, k0); i < this.index.length && this.index[i]! <= k1; i++) m = Math.max(m, this.value[i]!);
    return m;
  }

  /** The n values 0..n-1 (zeros where absent). */
  dense(n: number): Uint32Array {
    const out = new Uint32Array(n);
    for (let i = 0; i < this.index.length; i++) if (this.index[i]! < n) out[this.index[i]!] = this.value[i]!;
    return out;
  }

  max(): number {
    let m = 0;
    for (const v of this.value) m = Math.max(m, v);
    return m;
  }
}

function lowerBound(a: Uint32Array, k: number): number {
  let lo = 0;
  let hi = a.length;
  while (lo < hi) {
    const mid = (lo + hi) >>> 1;
    if (a[mid]! < k) lo = mid + 1;
    else hi = mid;
  }
  return lo;
}

// ---------- time ----------

/** The counting periods of a result: period k is [t0 + k·step, min(t0 + k·step + duration, t1)). */
export interface Periods {
  t0: number;
  t1: number;
  step: number;
  duration: number;
  /** K, the number of periods. */
  steps: number;
}

export function periodStart(p: Periods, k: number): number {
  return p.t0 + k * p.step;
}

export function periodEnd(p: Periods, k: number): number {
  return Math.min(p.t0 + k * p.step + p.duration, p.t1);
}

/**
 * The counting period shown at instant t: the last period that starts at or before t (when duration >
 * step, periods overlap and t lies in several; the latest is the one whose count is "now"). -1 outside
 * [t0, t1).
 */
export function stepAt(p: Periods, t: number): number {
  if (!Number.isFinite(t) || t < p.t0 || t >= p.t1 || p.steps <= 0) return -1;
  return Math.min(p.steps - 1, Math.floor((t - p.t0) / p.step));
}

/**
 * The periods a time window [w0, w1) shows: those lying wholly inside it, as an inclusive range; a window
 * shorter than one period shows the period at w0. null when the window misses the periods.
 */
export function stepsInWindow(p: Periods, w0: number, w1: number): [number, number] | null {
  if (!(w1 > w0) || p.steps <= 0) return null;
  const first = Math.max(0, Math.ceil((w0 - p.t0) / p.step));
  let last = Math.min(p.steps - 1, Math.floor((w1 - p.t0) / p.step));
  while (last >= first && periodEnd(p, last) > w1) last--;
  if (last >= first) return [first, last];
  const k = stepAt(p, Math.max(w0, p.t0));
  return k >= 0 && w1 > p.t0 ? [k, k] : null;
}

// ---------- colour against the thresholds ----------

/**
 * The class of an occupancy against a volume's thresholds (counts.hpp: a hotspot needs the occupancy to
 * EXCEED a threshold): empty (0), low (at most 75 % of the lower threshold), near (above 75 %, not above
 * any threshold), sustained (above the sustained threshold, not above the peak), peak (above the peak
 * threshold), count (no threshold: flights but nothing to compare with).
 */
export type OccClass = 'empty' | 'low' | 'near' | 'sustained' | 'peak' | 'count';

/** Share of the lower threshold above which a volume is "near" it. */
export const NEAR_FRACTION = 0.75;

export function occupancyClass(occ: number, peak: number | null, sustained: number | null): OccClass {
  if (!(occ > 0)) return 'empty';
  if (peak !== null && occ > peak) return 'peak';
  if (sustained !== null && occ > sustained) return 'sustained';
  const ref = sustained !== null && peak !== null ? Math.min(sustained, peak) : (sustained ?? peak);
  if (ref === null) return 'count';
  return occ > NEAR_FRACTION * ref ? 'near' : 'low';
}

/** Severity order (map: the worst class of the volumes stacked over one footprint is drawn). */
export const CLASS_RANK: Record<OccClass, number> = { empty: 0, count: 1, low: 2, near: 3, sustained: 4, peak: 5 };

/** The legend: class, colour, label (in severity order, empty left out). */
export const CLASS_STYLE: { cls: OccClass; color: string; label: string }[] = [
  { cls: 'count', color: '#7aa2f7', label: 'flights, no threshold' },
  { cls: 'low', color: '#2bb673', label: `≤ ${NEAR_FRACTION * 100} % of threshold` },
  { cls: 'near', color: '#f2c94c', label: `> ${NEAR_FRACTION * 100} % of threshold` },
  { cls: 'sustained', color: '#f2994a', label: '> sustained threshold' },
  { cls: 'peak', color: '#eb4d4b', label: '> peak threshold' },
];

export function classColor(c: OccClass): string {
  return CLASS_STYLE.find((s) => s.cls === c)?.color ?? 'rgba(0,0,0,0)';
}

// ---------- the model ----------

export interface Volume {
  id: string;
  kind: 'cell' | 'sector';
  /** [west, south, east, north] degrees. */
  bbox: [number, number, number, number];
  lowerM: number;
  upperM: number;
  peak: number | null;
  sustained: number | null;
  maxOccupancy: number;
  totalEntries: number;
  occupancy: SparseSeries;
  entries: SparseSeries;
  /** Volumes over the same ground footprint share it (grid cells of one column; a sector is its own). */
  footprint: string;
}

export interface Hotspot extends WireHotspot {
  /** Index into CongestionModel.volumes. */
  volumeIndex: number;
}

export interface CongestionModel {
  job: string;
  dataset: string;
  grid: boolean;
  periods: Periods;
  entryStep: number;
  entryWindow: number;
  entryWindows: number;
  flights: number;
  volumes: Volume[];
  byId: Map<string, number>;
  hotspots: Hotspot[];
  hotspotsTotal: number;
  separation: SeparationEvent[] | null;
}

const num = (v: unknown, what: string): number => {
  if (typeof v !== 'number' || !Number.isFinite(v)) throw new Error(`congestion result: ${what} is not a number`);
  return v;
};
const thr = (v: unknown, what: string): number | null => (v === null || v === undefined ? null : num(v, what));

/** Reads the JSON result; throws Error naming what is malformed. */
export function parseResult(w: CongestionResultWire, job = w.job ?? ''): CongestionModel {
  const c = w.counts;
  const volumes: Volume[] = [];
  const byId = new Map<string, number>();
  for (const v of c?.volumes ?? []) {
    const vol = toVolume(v);
    byId.set(vol.id, volumes.length);
    volumes.push(vol);
  }
  const hotspots: Hotspot[] = (c?.hotspots ?? []).map((hs) => {
    const volumeIndex = byId.get(hs.volume);
    if (volumeIndex === undefined) throw new Error(`congestion result: hotspot of unknown volume ${hs.volume}`);
    return { ...hs, volumeIndex };
  });
  return {
    job,
    dataset: w.dataset,
    grid: c ? c.volumes_kind === 'grid' : !('sectors' in w.volumes),
    periods: c
      ? { t0: num(c.t0, 't0'), t1: num(c.t1, 't1'), step: num(c.step, 'step'), duration: num(c.duration, 'duration'), steps: num(c.steps, 'steps') }
      : { t0: w.separation?.t0 ?? 0, t1: w.separation?.t1 ?? 0, step: 60, duration: 60, steps: 0 },
    entryStep: c?.entry_step ?? 0,
    entryWindow: c?.entry_window ?? 0,
    entryWindows: c?.entry_windows ?? 0,
    flights: c?.flights ?? w.separation?.flights ?? 0,
    volumes,
    byId,
    hotspots,
    hotspotsTotal: c?.hotspots_total ?? 0,
    separation: w.separation ? w.separation.events : null,
  };
}

function toVolume(v: WireVolume): Volume {
  const bbox: [number, number, number, number] = [num(v.west, 'west'), num(v.south, 'south'), num(v.east, 'east'), num(v.north, 'north')];
  return {
    id: v.id,
    kind: v.kind,
    bbox,
    lowerM: num(v.lower_m, 'lower_m'),
    upperM: num(v.upper_m, 'upper_m'),
    peak: thr(v.peak, 'peak'),
    sustained: thr(v.sustained, 'sustained'),
    maxOccupancy: v.max_occupancy,
    totalEntries: v.total_entries,
    occupancy: SparseSeries.fromWire(v.occupancy, `${v.id} occupancy`),
    entries: SparseSeries.fromWire(v.entries, `${v.id} entries`),
    footprint: v.kind === 'cell' ? bbox.join(',') : `sector:${v.id}`,
  };
}

/** What one volume shows: its occupancy (at a period, or the largest over a range of periods) and class. */
export interface VolumeState {
  occupancy: number;
  cls: OccClass;
}

export function volumeState(v: Volume, range: [number, number] | null): VolumeState {
  const occ = range ? v.occupancy.maxIn(range[0], range[1]) : 0;
  return { occupancy: occ, cls: occupancyClass(occ, v.peak, v.sustained) };
}

/**
 * The state of every footprint: the worst volume stacked over it (class first, then occupancy, then the
 * lower volume), and that volume's index. Footprints whose volumes are all empty are left out.
 */
export function footprintStates(m: CongestionModel, range: [number, number] | null): Map<string, { volume: number } & VolumeState> {
  const out = new Map<string, { volume: number } & VolumeState>();
  if (!range) return out;
  m.volumes.forEach((v, i) => {
    const s = volumeState(v, range);
    if (s.cls === 'empty') return;
    const cur = out.get(v.footprint);
    if (!cur || CLASS_RANK[s.cls] > CLASS_RANK[cur.cls] || (CLASS_RANK[s.cls] === CLASS_RANK[cur.cls] && s.occupancy > cur.occupancy)) {
      out.set(v.footprint, { volume: i, ...s });
    }
  });
  return out;
}

// ---------- map geometry ----------

/** One footprint on the map: a cell column's rectangle or a sector's polygon ([lon, lat], closed). */
export interface Footprint {
  key: string;
  ring: [number, number][];
  sector: boolean;
}

/** One rectangle per grid column (the cells stacked over it share it). */
export function gridFootprints(volumes: readonly Volume[]): Footprint[] {
  const seen = new Set<string>();
  const out: Footprint[] = [];
  for (const v of volumes) {
    if (seen.has(v.footprint)) continue;
    seen.add(v.footprint);
    const [w, s, e, n] = v.bbox;
    out.push({
      key: v.footprint,
      sector: false,
      ring: [
        [w, s],
        [e, s],
        [e, n],
        [w, n],
        [w, s],
      ],
    });
  }
  return out;
}

/** The sectors' polygons from the stored GeoJSON, matched to the result's volumes by name. */
export function sectorFootprints(fc: FeatureCollection, volumes: readonly Volume[]): Footprint[] {
  const byName = new Map(volumes.map((v) => [v.id, v]));
  const out: Footprint[] = [];
  for (const f of fc.features) {
    const name = (f.properties as { name?: unknown } | null)?.name;
    const v = typeof name === 'string' ? byName.get(name) : undefined;
    if (!v || f.geometry.type !== 'Polygon') continue;
    const ring = f.geometry.coordinates[0]!.map((c) => [c[0]!, c[1]!] as [number, number]);
    // The upload may leave the ring open (the server's parser accepts both); the map needs it closed.
    const [a, z] = [ring[0], ring[ring.length - 1]];
    if (a && z && (a[0] !== z[0] || a[1] !== z[1])) ring.push([a[0], a[1]]);
    out.push({ key: v.footprint, sector: true, ring });
  }
  return out;
}

/** The middle of the two aircraft at the CPA ([lon, lat]; across 180° the short way). */
export function cpaPoint(e: SeparationEvent): [number, number] {
  const { a, b } = e.cpa;
  let dl = b.lon - a.lon;
  if (dl > 180) dl -= 360;
  if (dl < -180) dl += 360;
  let lon = a.lon + dl / 2;
  if (lon >= 180) lon -= 360;
  if (lon < -180) lon += 360;
  return [lon, (a.lat + b.lat) / 2];
}

// ---------- hotspots ----------

export type HotspotOrder = 'excess' | 'duration';

/**
 * Hotspots ranked: by excess (largest first; then the longer, then the earlier), or by duration (longest
 * first; then the larger excess, then the earlier). Ties last by volume id and kind, so the order is total.
 */
export function rankHotspots<T extends WireHotspot>(hs: readonly T[], by: HotspotOrder): T[] {
  const dur = (x: WireHotspot) => x.end - x.start;
  const kindRank = (k: HotspotKind) => (k === 'peak' ? 0 : 1);
  return [...hs].sort((a, b) => {
    const primary = by === 'excess' ? b.excess - a.excess || dur(b) - dur(a) : dur(b) - dur(a) || b.excess - a.excess;
    return primary || a.start - b.start || (a.volume < b.volume ? -1 : a.volume > b.volume ? 1 : 0) || kindRank(a.kind) - kindRank(b.kind);
  });
}

/** Events in progress at t (t_start <= t <= t_end). */
export function eventsAt(events: readonly SeparationEvent[], t: number): SeparationEvent[] {
  return events.filter((e) => e.t_start <= t && t <= e.t_end);
}

// ---------- CSV ----------

/** Parses RFC 4180 CSV (quoted fields with "" escapes and embedded commas or newlines); rows of fields. */
export function parseCsv(text: string): string[][] {
  const rows: string[][] = [];
  let row: string[] = [];
  let field = '';
  let quoted = false;
  let i = 0;
  const n = text.length;
  while (i < n) {
    const ch = text[i]!;
    if (quoted) {
      if (ch === '"') {
        if (text[i + 1] === '"') {
          field += '"';
          i += 2;
          continue;
        }
        quoted = false;
      } else field += ch;
      i++;
      continue;
    }
    if (ch === '"' && field === '') quoted = true;
    else if (ch === ',') {
      row.push(field);
      field = '';
    } else if (ch === '\n' || ch === '\r') {
      if (ch === '\r' && text[i + 1] === '\n') i++;
      row.push(field);
      rows.push(row);
      row = [];
      field = '';
    } else field += ch;
    i++;
  }
  if (quoted) throw new Error('CSV: unterminated quoted field');
  if (field !== '' || row.length > 0) {
    row.push(field);
    rows.push(row);
  }
  return rows;
}

function table(text: string, header: string): string[][] {
  const rows = parseCsv(text);
  if (rows.length === 0 || rows[0]!.join(',') !== header) throw new Error(`CSV: expected the header "${header}", got "${rows[0]?.join(',') ?? ''}"`);
  const width = header.split(',').length;
  rows.slice(1).forEach((r, i) => {
    if (r.length !== width) throw new Error(`CSV: row ${i + 2} has ${r.length} fields, not ${width}`);
  });
  return rows.slice(1);
}

const csvNum = (s: string, what: string): number => {
  const v = Number(s);
  if (s.trim() === '' || !Number.isFinite(v)) throw new Error(`CSV: ${what} "${s}" is not a number`);
  return v;
};

export interface SeriesRow {
  volume: string;
  series: 'occupancy' | 'entries';
  index: number;
  start: number;
  end: number;
  value: number;
}

/** The "series" table (volume,series,index,start,end,value). */
export function parseSeriesCsv(text: string): SeriesRow[] {
  return table(text, 'volume,series,index,start,end,value').map(([volume, series, index, start, end, value]) => {
    if (series !== 'occupancy' && series !== 'entries') throw new Error(`CSV: unknown series "${series}"`);
    return { volume: volume!, series, index: csvNum(index!, 'index'), start: csvNum(start!, 'start'), end: csvNum(end!, 'end'), value: csvNum(value!, 'value') };
  });
}

/** A hotspot as its CSV table has it: the wire hotspot with flight ids only. */
export type HotspotRow = Omit<WireHotspot, 'flights'> & { flights: number[] };

/** The "hotspots" table (flight ids joined by spaces). */
export function parseHotspotsCsv(text: string): HotspotRow[] {
  return table(text, 'volume,kind,first_step,last_step,start,end,peak,peak_time,threshold,excess,flights').map((r) => {
    const [volume, kind, first, last, start, end, peak, peakT, threshold, excess, flights] = r as [string, string, string, string, string, string, string, string, string, string, string];
    if (kind !== 'peak' && kind !== 'sustained') throw new Error(`CSV: unknown hotspot kind "${kind}"`);
    return {
      volume,
      kind,
      first_step: csvNum(first, 'first_step'),
      last_step: csvNum(last, 'last_step'),
      start: csvNum(start, 'start'),
      end: csvNum(end, 'end'),
      peak: csvNum(peak, 'peak'),
      peak_time: csvNum(peakT, 'peak_time'),
      threshold: csvNum(threshold, 'threshold'),
      excess: csvNum(excess, 'excess'),
      flights: flights.trim() === '' ? [] : flights.trim().split(/\s+/).map((f) => csvNum(f, 'flight id')),
    };
  });
}

/** Sparse series per volume from the series table (the same SparseSeries the JSON gives). */
export function seriesFromCsv(rows: readonly SeriesRow[]): Map<string, { occupancy: SparseSeries; entries: SparseSeries }> {
  const acc = new Map<string, { occupancy: [number, number][]; entries: [number, number][] }>();
  for (const r of rows) {
    let a = acc.get(r.volume);
    if (!a) acc.set(r.volume, (a = { occupancy: [], entries: [] }));
    a[r.series].push([r.index, r.value]);
  }
  const out = new Map<string, { occupancy: SparseSeries; entries: SparseSeries }>();
  const mk = (pairs: [number, number][]) => {
    pairs.sort((x, y) => x[0] - y[0]);
    return new SparseSeries(Uint32Array.from(pairs, (p) => p[0]), Uint32Array.from(pairs, (p) => p[1]));
  };
  for (const [v, a] of acc) out.set(v, { occupancy: mk(a.occupancy), entries: mk(a.entries) });
  return out;
}
