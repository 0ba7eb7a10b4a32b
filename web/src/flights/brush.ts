// Maths of the time-window brush over the time histogram: pixel ↔ time, snapping to bin edges,
// and the half-open window [t0, t1) that a drag, a move or a resize produces.

import type { TimeHistogram } from '../api/types';

/** A time range [start, end) in Unix seconds. */
export interface Span {
  start: number;
  end: number;
}

/** Bins are [origin + i·step, origin + (i+1)·step). */
export interface BinGrid {
  origin: number;
  step: number;
}

export type DragMode = 'new' | 'move' | 'start' | 'end';

export function gridOf(h: TimeHistogram): BinGrid {
  return { origin: h.t0, step: h.bin_seconds };
}

/**
 * The brush's x domain: the data set's time range, widened to cover every histogram bin.
 * `tMax` is the last sample's time, so the half-open domain ends one second after it.
 */
export function brushDomain(tMin: number, tMax: number, h?: TimeHistogram): Span {
  let start = tMin;
  let end = tMax + 1;
  if (h && h.counts.length > 0 && h.bin_seconds > 0) {
    start = Math.min(start, h.t0);
    end = Math.max(end, h.t0 + h.counts.length * h.bin_seconds);
  }
  return { start, end };
}

export function timeToX(t: number, d: Span, width: number): number {
  const span = d.end - d.start;
  return span > 0 ? ((t - d.start) / span) * width : 0;
}

export function xToTime(x: number, d: Span, width: number): number {
  const f = width > 0 ? Math.min(1, Math.max(0, x / width)) : 0;
  return d.start + f * (d.end - d.start);
}

function clamp(v: number, lo: number, hi: number): number {
  return Math.min(hi, Math.max(lo, v));
}

/** Snaps a time to the nearest bin edge ('round'), or the edge at or below ('floor') / at or above ('ceil'). */
export function snapToGrid(t: number, g: BinGrid, mode: 'round' | 'floor' | 'ceil' = 'round'): number {
  if (!(g.step > 0)) return t;
  const k = (t - g.origin) / g.step;
  // A tolerance keeps edges computed in floating point (origin + i·step) on their own bin.
  const eps = 1e-9;
  const i = mode === 'floor' ? Math.floor(k + eps) : mode === 'ceil' ? Math.ceil(k - eps) : Math.round(k);
  return g.origin + i * g.step;
}

/**
 * The window a drag from time a to time b selects: ordered, widened outwards to whole bins,
 * clamped to the domain, and at least one bin wide.
 */
export function windowFromDrag(a: number, b: number, d: Span, g: BinGrid): Span {
  const lo = Math.min(a, b);
  const hi = Math.max(a, b);
  let start = clamp(snapToGrid(lo, g, 'floor'), d.start, d.end);
  let end = clamp(snapToGrid(hi, g, 'ceil'), d.start, d.end);
  if (end - start < g.step) {
    end = Math.min(d.end, start + g.step);
    start = Math.max(d.start, end - g.step);
  }
  return { start, end };
}

/** Shifts a window by dt (snapped to whole bins), keeping its width and staying inside the domain. */
export function moveWindow(w: Span, dt: number, d: Span, g: BinGrid): Span {
  const width = w.end - w.start;
  const steps = g.step > 0 ? Math.round(dt / g.step) : 0;
  const start = clamp(w.start + steps * g.step, d.start, Math.max(d.start, d.end - width));
  return { start, end: start + Math.min(width, d.end - d.start) };
}

/** Moves one edge of a window to time t (snapped), never letting the window become narrower than one bin. */
export function resizeWindow(w: Span, edge: 'start' | 'end', t: number, d: Span, g: BinGrid): Span {
  const snapped = clamp(snapToGrid(t, g), d.start, d.end);
  if (edge === 'start') return { start: Math.min(snapped, w.end - g.step), end: w.end };
  return { start: w.start, end: Math.max(snapped, w.start + g.step) };
}

/** What a pointer press at pixel x does, given the current window's pixel extent (or none). */
export function hitTest(x: number, win: { x0: number; x1: number } | null, handle = 6): DragMode {
  if (!win) return 'new';
  if (Math.abs(x - win.x0) <= handle) return 'start';
  if (Math.abs(x - win.x1) <= handle) return 'end';
  if (x > win.x0 && x < win.x1) return 'move';
  return 'new';
}

/** Whether histogram bin i overlaps the half-open window. */
export function binInWindow(i: number, g: BinGrid, w: Span): boolean {
  const b0 = g.origin + i * g.step;
  const b1 = b0 + g.step;
  return b0 < w.end && b1 > w.start;
}

/** True when the window covers the whole domain (the same as no time filter). */
export function coversDomain(w: Span, d: Span): boolean {
  return w.start <= d.start && w.end >= d.end;
}

/**
 * The brush's resolution: whole seconds (the API's t0/t1 are integer seconds), whatever the histogram's
 * bins. A selection is never snapped to bins.
 */
export const SECOND_GRID: BinGrid = { origin: 0, step: 1 };

/** The narrowest time view the axis zooms to (seconds): a few pixels per second on any plot. */
export const MIN_VIEW_SECONDS = 30;

/**
 * The view after zooming by `factor` (> 1 zooms in) about time `at`: `at` keeps its place on screen, the
 * view never gets narrower than `minSpan` nor leaves the domain (a view wider than it becomes it).
 */
export function zoomView(view: Span, domain: Span, at: number, factor: number, minSpan = MIN_VIEW_SECONDS): Span {
  const full = domain.end - domain.start;
  const span = Math.min(full, Math.max(Math.min(minSpan, full), (view.end - view.start) / factor));
  const f = view.end > view.start ? (at - view.start) / (view.end - view.start) : 0.5;
  return clampView({ start: at - f * span, end: at - f * span + span }, domain);
}

/** Shifts a view inside the domain, keeping its width (at most the domain's). */
export function clampView(v: Span, domain: Span): Span {
  const span = Math.min(v.end - v.start, domain.end - domain.start);
  const start = clamp(v.start, domain.start, domain.end - span);
  return { start, end: start + span };
}

const NUDGE_STEPS = [1, 5, 10, 30, 60, 300, 900, 3600, 10800, 21600, 86400];

/** The keyboard nudge for a view (seconds): the largest round step at most 1/100 of it, at least 1 s. */
export function nudgeStep(view: Span): number {
  const want = (view.end - view.start) / 100;
  let step = 1;
  for (const s of NUDGE_STEPS) if (s <= want) step = s;
  return step;
}

const ISO_RE = /^(\d{4})-(\d{2})-(\d{2})(?:[T ](\d{2}):(\d{2})(?::(\d{2})(?:\.(\d+))?)?)?\s*(Z|[+-]\d{2}:?\d{2})?$/i;

/**
 * An ISO 8601 date-time ("2018-01-01T10:15:30Z", "2018-01-01 10:15", "2018-01-01T11:15+01:00",
 * "2018-01-01") as Unix seconds; no zone means UTC, as every time on the dashboard is. Null when the text
 * is not one, or names an impossible date or time (2018-02-30, 24:00).
 */
export function parseIsoUtc(text: string): number | null {
  const m = ISO_RE.exec(text.trim());
  if (!m) return null;
  const [y, mo, d, hh = '0', mi = '0', ss = '0', frac, zone] = m.slice(1) as (string | undefined)[];
  const Y = Number(y), M = Number(mo), D = Number(d), H = Number(hh), Mi = Number(mi), S = Number(ss);
  if (M < 1 || M > 12 || D < 1 || H > 23 || Mi > 59 || S > 59) return null;
  const ms = Date.UTC(Y, M - 1, D, H, Mi, S);
  if (new Date(ms).getUTCDate() !== D) return null;
  let t = ms / 1000 + (frac ? Number(`0.${frac}`) : 0);
  if (zone && zone.toUpperCase() !== 'Z') {
    const z = /^([+-])(\d{2}):?(\d{2})$/.exec(zone)!;
    const off = (Number(z[2]) * 60 + Number(z[3])) * 60;
    t -= z[1] === '+' ? off : -off;
  }
  return t;
}

/** Unix seconds as ISO 8601 UTC to the second: "2018-01-01T10:15:30Z". */
export function formatIsoUtc(t: number): string {
  return new Date(Math.round(t) * 1000).toISOString().replace(/\.\d{3}Z$/, 'Z');
}
