// The gaze dashboard's URL hash: "#gaze" or
// "#gaze?g=ID&stimulus=S&participant=P&t0=0&t1=5000&method=idt&types=fixation,saccade&what=fixations
//  &how=log&aoi=face:r:10,20,200,180;sky:p:0,0,1024,0,512,300" (src/route.ts gives other hashes to the
// other dashboards). AOIs live in the hash, so a shared link shows the same areas.

import { GAZE_EVENT_TYPES, GAZE_METHODS, type Aoi, type GazeEventType, type GazeMethod, type GazeTileWhat } from '../api/gazeTypes';

export function isGazeHash(hash: string): boolean {
  return /^#gaze(?:$|[?/&])/.test(hash);
}

export interface GazeRoute {
  dataset: string | null;
  stimulus: string | null;
  participant: string | null;
  /** Time window relative to each recording's first sample (ms). */
  t0: number | null;
  t1: number | null;
  method: GazeMethod;
  /** Event types listed and drawn (saccades as arrows); default fixations and saccades. */
  types: GazeEventType[];
  what: GazeTileWhat;
  how: 'linear' | 'log' | 'eq_hist';
  aois: Aoi[];
}

export const DEFAULT_TYPES: readonly GazeEventType[] = ['fixation', 'saccade'];

/** An AOI name as the hash and the table show it: letters, digits, space, _ - . (1..32 characters). */
export const AOI_NAME = /^[A-Za-z0-9 _.-]{1,32}$/;

const num = (s: string) => (s.trim() !== '' && Number.isFinite(Number(s)) ? Number(s) : null);
/** A coordinate as the hash keeps it: at most 2 decimals (hundredths of a stimulus pixel). */
const coord = (v: number) => String(Math.round(v * 100) / 100);

/** "face:r:10,20,200,180;sky:p:0,0,1024,0,512,300" → AOIs; malformed entries are dropped. */
export function parseAois(text: string | null): Aoi[] {
  const out: Aoi[] = [];
  const names = new Set<string>();
  for (const part of (text ?? '').split(';')) {
    const m = /^(.+):([rp]):([-0-9.,eE]+)$/.exec(part);
    if (!m) continue;
    const name = m[1]!;
    if (!AOI_NAME.test(name) || names.has(name)) continue;
    const v = m[3]!.split(',').map(num);
    if (v.some((x) => x === null)) continue;
    const xs = v as number[];
    if (m[2] === 'r') {
      if (xs.length !== 4) continue;
      const [a, b, c, d] = xs as [number, number, number, number];
      if (!(Math.abs(c - a) > 0 && Math.abs(d - b) > 0)) continue;
      out.push({ name, rect: [Math.min(a, c), Math.min(b, d), Math.max(a, c), Math.max(b, d)] });
    } else {
      if (xs.length < 6 || xs.length % 2) continue;
      const polygon: [number, number][] = [];
      for (let i = 0; i < xs.length; i += 2) polygon.push([xs[i]!, xs[i + 1]!]);
      out.push({ name, polygon });
    }
    names.add(name);
  }
  return out;
}

export function formatAois(aois: readonly Aoi[]): string {
  return aois
    .map((a) => ('rect' in a ? `${a.name}:r:${a.rect.map(coord).join(',')}` : `${a.name}:p:${a.polygon.flatMap((p) => p.map(coord)).join(',')}`))
    .join(';');
}

export function parseGazeHash(hash: string): GazeRoute {
  const q = isGazeHash(hash) ? new URLSearchParams(hash.replace(/^#gaze\/?/, '').replace(/^[?&]/, '')) : new URLSearchParams();
  const str = (k: string) => {
    const v = q.get(k);
    return v && v.trim() ? v.trim() : null;
  };
  const t0 = num(q.get('t0') ?? '');
  const t1 = num(q.get('t1') ?? '');
  const method = q.get('method') as GazeMethod | null;
  const types = q.has('types')
    ? (q.get('types') ?? '').split(',').filter((t): t is GazeEventType => (GAZE_EVENT_TYPES as readonly string[]).includes(t))
    : [...DEFAULT_TYPES];
  const how = q.get('how');
  return {
    dataset: str('g'),
    stimulus: str('stimulus'),
    participant: str('participant'),
    t0: t0 !== null && t0 >= 0 ? t0 : null,
    t1: t1 !== null && t1 >= 0 && (t0 === null || t1 > t0) ? t1 : null,
    method: method && GAZE_METHODS.includes(method) ? method : 'ivt',
    types,
    what: q.get('what') === 'samples' ? 'samples' : 'fixations',
    how: how === 'linear' || how === 'eq_hist' ? how : 'log',
    aois: parseAois(q.get('aoi')),
  };
}

export function gazeHash(r: Partial<GazeRoute>): string {
  const q = new URLSearchParams();
  if (r.dataset) q.set('g', r.dataset);
  if (r.stimulus) q.set('stimulus', r.stimulus);
  if (r.participant) q.set('participant', r.participant);
  if (r.t0 !== null && r.t0 !== undefined) q.set('t0', String(r.t0));
  if (r.t1 !== null && r.t1 !== undefined) q.set('t1', String(r.t1));
  if (r.method && r.method !== 'ivt') q.set('method', r.method);
  if (r.types && (r.types.length !== DEFAULT_TYPES.length || r.types.some((t, i) => t !== DEFAULT_TYPES[i]))) q.set('types', r.types.join(','));
  if (r.what && r.what !== 'fixations') q.set('what', r.what);
  if (r.how && r.how !== 'log') q.set('how', r.how);
  if (r.aois && r.aois.length) q.set('aoi', formatAois(r.aois));
  const s = q.toString().replace(/%2C/g, ',').replace(/%3A/g, ':').replace(/%3B/g, ';');
  return s ? `#gaze?${s}` : '#gaze';
}
