// Teat trajectories over time: x, y and z of each teat's tip (mm) against the frame, the tracker's
// estimate solid and the ground truth dashed, and each teat's 3D error when truth exists. Every plot
// shares the frame axis and the cursor; clicking one seeks.

import { TEAT_NAMES } from '../api/trackerLog';
import { h, sectionHead } from '../lib/dom';
import { AxisSurface } from './axisSurface';
import { xOfFrame } from './frameAxis';
import type { FrameStore } from './frameStore';
import { TEAT_COLORS } from './palette';
import { extent, teatSeries, type TeatSeries } from './series';

type Row = 'x' | 'y' | 'z' | 'error';
const ROWS: { key: Row; label: string }[] = [
  { key: 'x', label: 'x (mm)' },
  { key: 'y', label: 'y (mm)' },
  { key: 'z', label: 'z (mm)' },
  { key: 'error', label: '3D error (mm)' },
];
const PAD_T = 4;
const PAD_B = 4;

export class Trajectories {
  readonly root: HTMLElement;
  readonly surfaces: AxisSurface[];
  private store: FrameStore | null = null;
  private series: TeatSeries[] = [];
  private seriesVersion = -1;
  private readonly shown = [true, true, true, true];

  constructor(onSeek: (frame: number) => void) {
    this.surfaces = ROWS.map(
      (row) =>
        new AxisSurface({
          label: `Teat ${row.label} over frames; click to select a frame`,
          testid: `trajectory-${row.key}`,
          onSeek,
          draw: (ctx, w, hgt) => this.draw(row.key, ctx, w, hgt),
          describe: (f) => this.describe(row.key, f),
        }),
    );
    const toggles = TEAT_NAMES.map((name, i) => {
      const input = h('input', { type: 'checkbox', checked: true, 'data-testid': `trajectory-teat-${name}` });
      input.addEventListener('change', () => {
        this.shown[i] = input.checked;
        this.invalidate();
      });
      return h('label', { class: 'legend-item' }, input, h('span', { class: 'legend-line', style: `background:${TEAT_COLORS[i]}` }), name);
    });
    this.root = h(
      'section',
      { class: 'tracker-panel trajectories', 'aria-label': 'Teat trajectories', 'data-testid': 'trajectories' },
      sectionHead(
        'Teat trajectories',
        h('span', { class: 'legend' }, ...toggles, h('span', { class: 'muted small' }, 'estimate solid · truth dashed')),
      ),
      ...ROWS.map((row, i) => h('div', { class: 'trajectory-row' }, h('span', { class: 'trajectory-label muted' }, row.label), this.surfaces[i]!.root)),
    );
  }

  setStore(store: FrameStore): void {
    this.store = store;
    this.seriesVersion = -1;
    for (const s of this.surfaces) s.setFrames(store.frames);
  }

  setCursor(frame: number): void {
    for (const s of this.surfaces) s.setCursor(frame);
  }

  invalidate(): void {
    for (const s of this.surfaces) s.invalidate();
  }

  private ensureSeries() {
    const st = this.store;
    if (!st || st.version === this.seriesVersion) return;
    this.series = TEAT_NAMES.map((_, t) => teatSeries(st, t));
    this.seriesVersion = st.version;
    this.root.dataset.points = String(this.series.reduce((n, s) => n + s.estimate[0].filter(Number.isFinite).length, 0));
    this.root.dataset.truthPoints = String(this.series.reduce((n, s) => n + s.truth[0].filter(Number.isFinite).length, 0));
  }

  private arraysOf(row: Row, s: TeatSeries): { est: Float64Array; truth: Float64Array | null } {
    if (row === 'error') return { est: s.error, truth: null };
    const a = row === 'x' ? 0 : row === 'y' ? 1 : 2;
    return { est: s.estimate[a], truth: s.truth[a] };
  }

  private draw(row: Row, ctx: CanvasRenderingContext2D, w: number, hgt: number) {
    this.ensureSeries();
    const st = this.store;
    if (!st || st.frames === 0) return;
    const n = st.frames;
    const visible = this.series.map((s, i) => (this.shown[i] ? this.arraysOf(row, s) : null));
    const all = visible.flatMap((v) => (v ? (v.truth ? [v.est, v.truth] : [v.est]) : []));
    let [lo, hi] = extent(all);
    if (row === 'error') lo = 0;
    const y = (v: number) => PAD_T + (1 - (v - lo) / (hi - lo)) * (hgt - PAD_T - PAD_B);
    // Grid: the extremes.
    ctx.strokeStyle = '#222a35';
    ctx.lineWidth = 1;
    ctx.beginPath();
    ctx.moveTo(0, Math.round(y(lo)) + 0.5);
    ctx.lineTo(w, Math.round(y(lo)) + 0.5);
    ctx.moveTo(0, Math.round(y(hi)) + 0.5);
    ctx.lineTo(w, Math.round(y(hi)) + 0.5);
    ctx.stroke();
    visible.forEach((v, i) => {
      if (!v) return;
      ctx.strokeStyle = TEAT_COLORS[i]!;
      if (v.truth) {
        ctx.globalAlpha = 0.8;
        ctx.setLineDash([4, 3]);
        ctx.lineWidth = 1;
        polyline(ctx, v.truth, w, n, y);
      }
      ctx.globalAlpha = 1;
      ctx.setLineDash([]);
      ctx.lineWidth = 1.5;
      polyline(ctx, v.est, w, n, y);
    });
    ctx.fillStyle = '#9aa5b3';
    ctx.font = '10px ui-monospace, monospace';
    ctx.fillText(fmt(hi), 3, PAD_T + 9);
    ctx.fillText(fmt(lo), 3, hgt - PAD_B - 2);
  }

  private describe(row: Row, f: number): string {
    this.ensureSeries();
    const parts = this.series.map((s, i) => {
      const { est, truth } = this.arraysOf(row, s);
      const e = est[f] ?? NaN;
      const t = truth ? truth[f] ?? NaN : NaN;
      return `${TEAT_NAMES[i]} ${fmt(e)}${truth ? `/${fmt(t)}` : ''}`;
    });
    return `frame ${f} · ${parts.join(' · ')}`;
  }
}

function fmt(v: number): string {
  return Number.isFinite(v) ? v.toFixed(Math.abs(v) < 10 ? 1 : 0) : '–';
}

/** A line through the finite values, broken at NaN. */
function polyline(ctx: CanvasRenderingContext2D, a: Float64Array, w: number, n: number, y: (v: number) => number) {
  ctx.beginPath();
  let pen = false;
  for (let i = 0; i < n; i++) {
    const v = a[i]!;
    if (!Number.isFinite(v)) {
      pen = false;
      continue;
    }
    const x = xOfFrame(i, w, n);
    if (pen) ctx.lineTo(x, y(v));
    else {
      ctx.moveTo(x, y(v));
      // A lone point still shows.
      if (!Number.isFinite(a[i + 1] ?? NaN)) ctx.lineTo(x + 0.5, y(v));
    }
    pen = true;
  }
  ctx.stroke();
}
