// Tolerant decoder of tracker frame records (proto/tracker_log.proto, canonical protobuf JSON) and of
// per-frame ground truth. Protobuf JSON omits fields at their default (0, false, empty, first enum value),
// writes non-finite doubles as the strings "NaN"/"Infinity" and 64-bit integers as strings; snake_case
// names are accepted too. Nothing here throws on odd input: unknown shapes decode to empty values.

export const TEAT_NAMES = ['FL', 'FR', 'RL', 'RR'] as const;
export type TeatName = (typeof TEAT_NAMES)[number];
/** Teat index pairs of ModelMetrics.pair_mm, in the logged order. */
export const TEAT_PAIRS: readonly (readonly [number, number])[] = [
  [0, 1],
  [2, 3],
  [0, 2],
  [1, 3],
  [0, 3],
  [1, 2],
];
export const PAIR_NAMES = TEAT_PAIRS.map(([a, b]) => `${TEAT_NAMES[a]}–${TEAT_NAMES[b]}`);

export type TrackerState = 'SEARCH' | 'TRACK' | 'LOST';
export type Vec3 = [number, number, number];

export interface Candidate {
  u: number;
  v: number;
  ncc: number;
  templateIndex: number;
  verified: boolean;
  tipMm: Vec3 | null;
  radiusMm: number;
  fitRmsMm: number;
  points: number;
  /** 0..3, or -1 when unassigned. */
  teat: number;
}

export interface ModelMetrics {
  pairMm: number[];
  pairErrorMm: number[];
  shapeCost: number;
  nccCost: number;
  cost: number;
  teatsMatched: number;
}

export interface TeatEstimate {
  tipMm: Vec3 | null;
  tipPx: [number, number] | null;
  visible: boolean;
  tracked: boolean;
  confidence: number;
  radiusMm: number;
}

export interface StageTimes {
  preprocessUs: number;
  detectUs: number;
  verifyUs: number;
  modelUs: number;
  totalUs: number;
}

export interface FrameRecord {
  index: number;
  timestampS: number;
  validPixels: number;
  flyingPixels: number;
  matches: number;
  verified: number;
  candidates: Candidate[];
  model: ModelMetrics;
  state: TrackerState;
  /** Always four, FL FR RL RR. */
  teats: TeatEstimate[];
  times: StageTimes;
}

export interface TruthTeat {
  name: string;
  tipMm: Vec3 | null;
  tipPx: [number, number] | null;
  visible: boolean;
  boxPx: [number, number, number, number] | null;
  visibleFraction: number;
  cupAttached: boolean;
}

export interface FrameTruth {
  teats: TruthTeat[];
}

type Obj = Record<string, unknown>;

function isObj(v: unknown): v is Obj {
  return typeof v === 'object' && v !== null && !Array.isArray(v);
}

function snake(name: string): string {
  return name.replace(/[A-Z]/g, (c) => `_${c.toLowerCase()}`);
}

/** The field under its lowerCamelCase or snake_case name. */
function field(o: Obj, name: string): unknown {
  if (name in o) return o[name];
  const s = snake(name);
  return s in o ? o[s] : undefined;
}

/** A number from a JSON number or a protobuf string ("12", "NaN", "Infinity", "-Infinity"); else `dflt`. */
export function toNumber(v: unknown, dflt = 0): number {
  if (typeof v === 'number') return v;
  if (typeof v === 'string') {
    if (v === 'NaN') return NaN;
    if (v === 'Infinity') return Infinity;
    if (v === '-Infinity') return -Infinity;
    const n = Number(v);
    return v.trim() !== '' && !Number.isNaN(n) ? n : dflt;
  }
  return dflt;
}

function num(o: Obj, name: string, dflt = 0): number {
  return toNumber(field(o, name), dflt);
}

function bool(o: Obj, name: string): boolean {
  const v = field(o, name);
  return v === true || v === 'true' || v === 1;
}

function numArray(v: unknown, len: number): number[] | null {
  if (!Array.isArray(v) || v.length < len) return null;
  return v.slice(0, len).map((x) => toNumber(x, NaN));
}

function vec3(v: unknown): Vec3 | null {
  if (isObj(v)) {
    // A message {x, y, z} (omitted members are 0).
    if (!('x' in v) && !('y' in v) && !('z' in v)) return null;
    return [toNumber(v.x), toNumber(v.y), toNumber(v.z)];
  }
  const a = numArray(v, 3);
  return a ? [a[0]!, a[1]!, a[2]!] : null;
}

function vec2(v: unknown): [number, number] | null {
  if (isObj(v)) {
    if (!('u' in v) && !('v' in v) && !('x' in v) && !('y' in v)) return null;
    return [toNumber(v.u ?? v.x), toNumber(v.v ?? v.y)];
  }
  const a = numArray(v, 2);
  return a ? [a[0]!, a[1]!] : null;
}

function list(v: unknown): unknown[] {
  return Array.isArray(v) ? v : [];
}

/** "STATE_TRACK", "TRACK", "track", 2 → "TRACK"; enum numbers as in the proto (SEARCH 1, TRACK 2, LOST 3). */
export function decodeState(v: unknown): TrackerState {
  if (typeof v === 'number') return v === 2 ? 'TRACK' : v === 3 ? 'LOST' : 'SEARCH';
  if (typeof v === 'string') {
    const s = v.toUpperCase().replace(/^STATE_/, '');
    if (s === 'TRACK' || s === 'TRACKING') return 'TRACK';
    if (s === 'LOST') return 'LOST';
  }
  return 'SEARCH';
}

export function decodeCandidate(raw: unknown): Candidate {
  const o = isObj(raw) ? raw : {};
  const teat = field(o, 'teat');
  return {
    u: num(o, 'u'),
    v: num(o, 'v'),
    ncc: num(o, 'ncc'),
    templateIndex: num(o, 'templateIndex'),
    verified: bool(o, 'verified'),
    tipMm: vec3(field(o, 'tipMm')),
    radiusMm: num(o, 'radiusMm'),
    fitRmsMm: num(o, 'fitRmsMm'),
    points: num(o, 'points'),
    // proto3 omits the default 0 (= FL); "unassigned" is written as -1.
    teat: teat === undefined || teat === null ? 0 : toNumber(teat, -1),
  };
}

function decodeModel(raw: unknown): ModelMetrics {
  const o = isObj(raw) ? raw : {};
  const six = (name: string) => {
    const a = list(field(o, name)).map((x) => toNumber(x, NaN));
    while (a.length < 6) a.push(NaN);
    return a.slice(0, 6);
  };
  return {
    pairMm: six('pairMm'),
    pairErrorMm: six('pairErrorMm'),
    shapeCost: num(o, 'shapeCost'),
    nccCost: num(o, 'nccCost'),
    cost: num(o, 'cost'),
    teatsMatched: num(o, 'teatsMatched'),
  };
}

export function decodeTeat(raw: unknown): TeatEstimate {
  const o = isObj(raw) ? raw : {};
  return {
    tipMm: vec3(field(o, 'tipMm')),
    tipPx: vec2(field(o, 'tipPx')),
    visible: bool(o, 'visible'),
    tracked: bool(o, 'tracked'),
    confidence: num(o, 'confidence'),
    radiusMm: num(o, 'radiusMm'),
  };
}

function decodeTimes(raw: unknown): StageTimes {
  const o = isObj(raw) ? raw : {};
  const t = {
    preprocessUs: num(o, 'preprocessUs'),
    detectUs: num(o, 'detectUs'),
    verifyUs: num(o, 'verifyUs'),
    modelUs: num(o, 'modelUs'),
    totalUs: num(o, 'totalUs', NaN),
  };
  if (!Number.isFinite(t.totalUs)) t.totalUs = t.preprocessUs + t.detectUs + t.verifyUs + t.modelUs;
  return t;
}

/** A frame record from its JSON mapping. `fallbackIndex` is used when the record omits `index` (= 0). */
export function decodeFrameRecord(raw: unknown, fallbackIndex = 0): FrameRecord {
  const o = isObj(raw) ? raw : {};
  const teats = list(field(o, 'teats')).slice(0, 4).map(decodeTeat);
  while (teats.length < 4) teats.push(decodeTeat(null));
  const idx = field(o, 'index');
  return {
    index: idx === undefined ? fallbackIndex : toNumber(idx, fallbackIndex),
    timestampS: num(o, 'timestampS'),
    validPixels: num(o, 'validPixels'),
    flyingPixels: num(o, 'flyingPixels'),
    matches: num(o, 'matches'),
    verified: num(o, 'verified'),
    candidates: list(field(o, 'candidates')).map(decodeCandidate),
    model: decodeModel(field(o, 'model')),
    state: decodeState(field(o, 'state')),
    teats,
    times: decodeTimes(field(o, 'times')),
  };
}

function decodeTruthTeat(raw: unknown, i: number): TruthTeat {
  const o = isObj(raw) ? raw : {};
  const rawBox = field(o, 'boxPx');
  const box = isObj(rawBox) ? [toNumber(rawBox.x), toNumber(rawBox.y), toNumber(rawBox.w), toNumber(rawBox.h)] : numArray(rawBox, 4);
  const name = field(o, 'name');
  return {
    name: typeof name === 'string' && name ? name : (TEAT_NAMES[i] ?? String(i)),
    tipMm: vec3(field(o, 'tipMm')),
    tipPx: vec2(field(o, 'tipPx')),
    visible: bool(o, 'visible'),
    boxPx: box ? [box[0]!, box[1]!, box[2]!, box[3]!] : null,
    visibleFraction: num(o, 'visibleFraction'),
    cupAttached: bool(o, 'cupAttached'),
  };
}

/** Ground truth of one frame, or null when there is none. Teats are put in FL FR RL RR order by name. */
export function decodeTruth(raw: unknown): FrameTruth | null {
  if (!isObj(raw)) return null;
  // The log's FrameTruthEntry {hasTruth, value}.
  const has = field(raw, 'hasTruth');
  if (has !== undefined || 'value' in raw) return has === false ? null : decodeTruth(raw.value);
  const teats = list(field(raw, 'teats')).map(decodeTruthTeat);
  if (teats.length === 0) return null;
  const order = (t: TruthTeat) => {
    const k = (TEAT_NAMES as readonly string[]).indexOf(t.name);
    return k < 0 ? 99 : k;
  };
  if (teats.every((t) => order(t) < 99)) teats.sort((a, b) => order(a) - order(b));
  return { teats };
}

/** Euclidean distance of two points, NaN when either is missing. */
export function distance3(a: Vec3 | null, b: Vec3 | null): number {
  if (!a || !b) return NaN;
  return Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

/**
 * Frame records and truth from the run frames route, whatever its envelope: a bare array of records,
 * `{frames: [...]}`, items shaped `{frame, truth}`, or a parallel `truth` array.
 */
export function decodeRunFrames(raw: unknown, from = 0): { frame: FrameRecord; truth: FrameTruth | null }[] {
  const body = isObj(raw) ? raw : {};
  const items = Array.isArray(raw) ? raw : list(body.frames ?? body.records ?? body.items);
  const truths = list(body.truth);
  return items.map((item, i) => {
    const wrapped = isObj(item) && isObj(item.frame);
    const rec = wrapped ? (item as Obj).frame : item;
    const frame = decodeFrameRecord(rec, from + i);
    if (wrapped && field(rec as Obj, 'index') === undefined && (item as Obj).index !== undefined) {
      frame.index = toNumber((item as Obj).index, from + i);
    }
    const truth = decodeTruth(wrapped ? (item as Obj).truth : isObj(item) ? item.truth : undefined) ?? decodeTruth(truths[i]);
    return { frame, truth };
  });
}
