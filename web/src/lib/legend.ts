// Legends that read values: where a colour scale's values sit along its bar, in the data's units.
// The density legend follows the server's own normalisation (compute/include/trailscope/density/shade.hpp:
// linear, log1p and histogram equalisation against one span per zoom, GET .../density/legend), so a tick
// at 40 % of the bar is the value the tiles paint with the colour at 40 %. Pure functions (unit-tested);
// `renderLegend` draws one with d3-axis.

import { scaleLinear, scaleLog } from 'd3-scale';
import { axisBottom } from 'd3-axis';
import { select } from 'd3-selection';
import type { DensityHow, DensityValue } from '../api/types';
import { FT_PER_M, KT_PER_MS, formatCompact, formatInt } from './format';

/**
 * The legend of a zoom's density tiles (GET /api/v1/datasets/{dataset}/density/legend): the span's ends
 * and `stops` at t = k/(n − 1), each with the colour the tiles give it (the minimum level applied) and the
 * smallest data value normalised to at least t (eq_hist: the span's quantiles).
 */
export interface DensityLegendAnswer {
  empty: boolean;
  lo: number;
  hi: number;
  value: DensityValue;
  how: DensityHow;
  z: number;
  unit: string;
  min_level: number;
  stops: { t: number; value: number; color: string }[];
}

/** One tick: its place along the bar (0 … 1) and its label. */
export interface LegendTick {
  at: number;
  label: string;
}

/**
 * v normalised to [0, 1] as the server's SpanStats::normalize does for linear and log1p shading
 * (compute/include/trailscope/density/shade.hpp); NaN stays NaN. (eq_hist needs the span's distribution:
 * its ticks come from the legend route's stops.)
 */
export function normalizeSpan(s: Pick<DensityLegendAnswer, 'empty' | 'lo' | 'hi'>, v: number, how: 'linear' | 'log'): number {
  if (Number.isNaN(v)) return v;
  if (s.empty) return 0;
  if (v <= s.lo) return 0;
  if (v >= s.hi) return 1;
  if (how === 'linear') return (v - s.lo) / (s.hi - s.lo);
  const o = Math.min(s.lo, 0);
  const a = Math.log1p(s.lo - o);
  const b = Math.log1p(s.hi - o);
  return (Math.log1p(v - o) - a) / (b - a);
}

/** The stops a density legend asks for: k/20, so that the quartiles 0, ¼, ½, ¾, 1 are stops. */
export const LEGEND_STOPS = 21;

/** A density value in the dashboard's units: counts as they are, altitude in flight levels, speed in knots. */
export function densityValueLabel(value: DensityValue, v: number): string {
  if (!Number.isFinite(v)) return '–';
  if (value === 'altitude') return `FL${String(Math.max(0, Math.round((v * FT_PER_M) / 100))).padStart(3, '0')}`;
  if (value === 'speed') return `${formatInt(v * KT_PER_MS)} kt`;
  return v >= 10_000 ? formatCompact(v) : v >= 10 || Number.isInteger(v) ? formatInt(v) : v.toFixed(1);
}

/** The unit a density legend's title names. */
export function densityUnit(value: DensityValue): string {
  return value === 'count' ? 'segments per pixel' : value === 'altitude' ? 'mean altitude' : 'mean ground speed';
}

/** d3 ticks in the value's display unit (feet / knots), converted back to the span's (metres / m/s). */
function niceValues(value: DensityValue, lo: number, hi: number, n: number, log: boolean): number[] {
  const k = value === 'altitude' ? FT_PER_M : value === 'speed' ? KT_PER_MS : 1;
  const a = lo * k;
  const b = hi * k;
  const ticks = log && a > 0 ? scaleLog().domain([a, b]).ticks(n) : scaleLinear().domain([a, b]).nice(n).ticks(n);
  return ticks.map((t) => t / k).filter((t) => t >= lo - 1e-9 && t <= hi + 1e-9);
}

/**
 * The density legend's ticks, `n` about how many fit: linear and log place round values in the data's
 * units where the server's normalisation puts them; eq_hist labels the quartiles of the shaded pixels
 * (the legend's stops at t = 0, ¼, ½, ¾, 1), since equal distances along its bar are equal shares of pixels.
 */
export function densityTicks(s: DensityLegendAnswer, how: DensityHow, n = 5): LegendTick[] {
  if (s.empty) return [];
  const label = (v: number) => densityValueLabel(s.value, v);
  if (!(s.hi > s.lo)) return [{ at: 0.5, label: label(s.lo) }];
  if (how === 'eq_hist') {
    const out: LegendTick[] = [];
    for (const q of [0, 0.25, 0.5, 0.75, 1]) {
      const stop = s.stops.find((x) => Math.abs(x.t - q) < 1e-9);
      if (stop) out.push({ at: q, label: label(stop.value) });
    }
    return out;
  }
  let vals = niceValues(s.value, s.lo, s.hi, n, how === 'log');
  if (how === 'log' && vals.length > n) {
    // scaleLog().ticks lists 1…9 per decade: keep the powers of ten and the ends.
    const decades = vals.filter((v) => Math.abs(Math.log10(v) - Math.round(Math.log10(v))) < 1e-9);
    vals = decades.length >= 2 ? decades : vals.filter((_, i) => i % Math.ceil(vals.length / n) === 0);
  }
  const ticks = vals.map((v) => ({ at: normalizeSpan(s, v, how), label: label(v) }));
  // The ends are always labelled: the bar's colours run from lo to hi.
  if (!ticks.some((t) => t.at < 0.04)) ticks.unshift({ at: 0, label: label(s.lo) });
  if (!ticks.some((t) => t.at > 0.96)) ticks.push({ at: 1, label: label(s.hi) });
  return dropCrowded(ticks);
}

/** Linear ticks of a fixed numeric scale (altitude ramps, run figures): round values between lo and hi. */
export function linearTicks(lo: number, hi: number, n: number, label: (v: number) => string): LegendTick[] {
  if (!(hi > lo)) return [{ at: 0.5, label: label(lo) }];
  return scaleLinear()
    .domain([lo, hi])
    .ticks(n)
    .map((v) => ({ at: (v - lo) / (hi - lo), label: label(v) }));
}

/** Drops ticks closer than `minGap` (fraction of the bar) to the one kept before them, always keeping the last. */
export function dropCrowded(ticks: LegendTick[], minGap = 0.12): LegendTick[] {
  const sorted = [...ticks].sort((a, b) => a.at - b.at);
  const out: LegendTick[] = [];
  for (const t of sorted) {
    const prev = out[out.length - 1];
    if (prev && t.at - prev.at < minGap) {
      if (t === sorted[sorted.length - 1]) out[out.length - 1] = t;
      continue;
    }
    out.push(t);
  }
  return out;
}

export interface LegendSpec {
  title: string;
  /** CSS colours spread evenly along the bar (low → high). */
  stops: readonly string[];
  ticks: readonly LegendTick[];
  /** Bar width in CSS pixels. */
  width: number;
  testid?: string;
  /** Shown under the bar (e.g. "eq_hist: quantiles of shaded pixels"). */
  note?: string;
}

let gradientSeq = 0;

/** Draws a legend into `el`: title, a gradient bar `width` px wide and a d3 axis with the ticks' labels. */
export function renderLegend(el: HTMLElement, spec: LegendSpec): void {
  const W = Math.max(40, Math.round(spec.width));
  const pad = 18;
  const barH = 10;
  el.replaceChildren();
  el.classList.add('value-legend');
  if (spec.testid) el.dataset.testid = spec.testid;
  el.dataset.width = String(W);
  el.dataset.ticks = spec.ticks.map((t) => t.label).join('|');
  const title = document.createElement('div');
  title.className = 'value-legend-title';
  title.textContent = spec.title;
  el.append(title);
  const id = `legend-grad-${++gradientSeq}`;
  const root = select(el)
    .append('svg')
    .attr('width', W + 2 * pad)
    .attr('height', barH + 22)
    .attr('role', 'img')
    .attr('aria-label', `${spec.title}: ${spec.ticks.map((t) => t.label).join(', ')}`);
  const grad = root.append('defs').append('linearGradient').attr('id', id);
  spec.stops.forEach((c, i) =>
    grad
      .append('stop')
      .attr('offset', `${spec.stops.length > 1 ? (i / (spec.stops.length - 1)) * 100 : 0}%`)
      .attr('stop-color', c),
  );
  root
    .append('rect')
    .attr('class', 'value-legend-bar')
    .attr('data-testid', spec.testid ? `${spec.testid}-bar` : null)
    .attr('x', pad)
    .attr('y', 0)
    .attr('width', W)
    .attr('height', barH)
    .attr('fill', `url(#${id})`);
  const x = scaleLinear().domain([0, 1]).range([pad, pad + W]);
  const labels = new Map(spec.ticks.map((t) => [t.at, t.label]));
  root
    .append('g')
    .attr('class', 'value-legend-axis')
    .attr('transform', `translate(0,${barH})`)
    .call(
      axisBottom(x)
        .tickValues(spec.ticks.map((t) => t.at))
        .tickFormat((v) => labels.get(v as number) ?? '')
        .tickSizeOuter(0)
        .tickSize(4),
    );
  if (spec.note) {
    const note = document.createElement('div');
    note.className = 'value-legend-note';
    note.textContent = spec.note;
    el.append(note);
  }
}

/**
 * CUBu's rainbow as the bundle tiles colour a polyline by its normalised length (mirror of
 * compute/src/bundling/render/render_math.cpp `rainbow`, dx = 0.8), as a CSS colour.
 */
export function cubuRainbow(v: number): string {
  const x = Math.min(1, Math.max(0, v));
  const dx = 0.8;
  const w = (6 - 2 * dx) * x + dx;
  const ch = (c: number) => Math.round(Math.min(1, Math.max(0, c / 2)) * 255);
  const r = ch(3 - Math.abs(w - 4) - Math.abs(w - 5));
  const g = ch(4 - Math.abs(w - 2) - Math.abs(w - 4));
  const b = ch(3 - Math.abs(w - 1) - Math.abs(w - 2));
  return `rgb(${r}, ${g}, ${b})`;
}

/** Kilometres per "Mercator degree" (TSBL lengths) at latitude `lat`: the projection's scale there. */
export function kmPerMercatorDegree(lat: number): number {
  return 111.32 * Math.cos((lat * Math.PI) / 180);
}

/** The bundle tiles' colour modes (compute/include/trailscope/bundling/render.hpp ColorBy). */
export type BundleColor = 'length' | 'direction' | 'density' | 'displacement' | 'flat';
export const BUNDLE_COLORS: readonly BundleColor[] = ['length', 'direction', 'density', 'displacement', 'flat'];

/** HSV (each 0 … 1, hue wrapping) → CSS, the mirror of render_math.cpp `hsv_to_rgb`. */
export function hsvCss(hue: number, s: number, v: number): string {
  const h = hue - Math.floor(hue);
  const sat = Math.min(1, Math.max(0, s));
  const val = Math.min(1, Math.max(0, v));
  const h6 = h * 6;
  const sector = Math.min(5, Math.floor(h6));
  const f = h6 - sector;
  const p = val * (1 - sat), q = val * (1 - sat * f), t = val * (1 - sat * (1 - f));
  const rgb = [[val, t, p], [q, val, p], [p, val, t], [p, q, val], [t, p, val], [val, p, q]][sector]!;
  const ch = (c: number) => Math.round(c * 255);
  return `rgb(${ch(rgb[0]!)}, ${ch(rgb[1]!)}, ${ch(rgb[2]!)})`;
}

/**
 * The colour the direction mode gives a trail heading at compass bearing `deg` (clockwise from north). The
 * tiles take hue = angle(end − start) / 2π in the Web Mercator plane, whose y grows southward: east is hue 0,
 * south ¼, west ½, north ¾; the saturation is the trail's normalised length^0.3 (full for the longest).
 */
export function bearingColor(deg: number, saturation = 1): string {
  return hsvCss((deg - 90) / 360, saturation, 1);
}

/** What a bundle colour legend needs to know of the bundle and the view. */
export interface BundleLegendInput {
  /** Shortest and longest trail, km (colour by length). */
  loKm: number;
  hiKm: number;
  /** bundling max_displacement: the cap of a point's displacement, as a fraction of its trail's length. */
  maxDisplacement: number;
  /** Colour map of the density and displacement modes (the tiles' cmap). */
  cmap: readonly string[];
  width: number;
}

/**
 * The legend of a bundle colour mode, ticks in the mode's units: length in km (shortest → longest trail of the
 * bundle), direction as compass bearings of travel, density as a fraction of the local maximum (the tiles'
 * locally normalised density ρn), displacement as a percentage of the trail's length (0 … max_displacement,
 * the normalisation of render.cpp). Flat has one colour: null.
 */
export function bundleLegend(mode: BundleColor, b: BundleLegendInput): LegendSpec | null {
  const fmtPct = (v: number) => `${Number.isInteger(v) ? v : v.toFixed(1)} %`;
  switch (mode) {
    case 'length':
      if (!(b.hiKm >= b.loKm)) return null;
      return {
        title: 'Bundle colour: trail length (km)',
        stops: Array.from({ length: 11 }, (_, i) => cubuRainbow(i / 10)),
        ticks: linearTicks(b.loKm, b.hiKm, 4, (v) => `≈${formatInt(v)}`),
        width: b.width,
        testid: 'bundle-legend',
        note: 'shortest → longest trail of this bundle',
      };
    case 'direction':
      return {
        title: 'Bundle colour: direction of travel (bearing)',
        stops: Array.from({ length: 13 }, (_, i) => bearingColor(i * 30)),
        ticks: [0, 90, 180, 270, 360].map((d) => ({ at: d / 360, label: `${['N', 'E', 'S', 'W', 'N'][d / 90]} ${d}°` })),
        width: b.width,
        testid: 'bundle-legend',
        note: 'start → end of each trail; paler = shorter',
      };
    case 'density':
      return {
        title: 'Bundle colour: density (× local maximum)',
        stops: b.cmap,
        ticks: linearTicks(0, 1, 4, (v) => (v === 0 ? '0' : v === 1 ? '1' : v.toFixed(2))),
        width: b.width,
        testid: 'bundle-legend',
        note: 'trails per pixel, normalised by the densest pixel nearby',
      };
    case 'displacement': {
      const hi = 100 * b.maxDisplacement;
      if (!(hi > 0)) return null;
      return {
        title: 'Bundle colour: displacement from the raw trail (% of its length)',
        stops: b.cmap,
        ticks: linearTicks(0, hi, 4, fmtPct),
        width: b.width,
        testid: 'bundle-legend',
        note: `capped at max_displacement = ${b.maxDisplacement}`,
      };
    }
    case 'flat':
      return null;
  }
}
