// A volume's time series: occupancy per counting period as a step line with its peak and sustained
// threshold lines, entry counts per rolling window below it, the time window as a band and a cursor at
// the current instant. Clicking the chart moves the clock there.

import { svg, mount } from '../../lib/dom';
import { formatUtcTime } from '../../lib/format';
import { periodEnd, periodStart, type CongestionModel, type Volume } from './model';

const W = 300;
const H = 178;
const M = { l: 30, r: 6, t: 8 };
const OCC_H = 96;
const GAP = 22;
const ENT_H = 40;

export class SeriesChart {
  readonly el: SVGSVGElement;
  private model: CongestionModel | null = null;
  private volume: Volume | null = null;
  private readonly cursor: SVGLineElement;
  private readonly band: SVGRectElement;
  private readonly body: SVGGElement;

  constructor(onSeek: (t: number) => void) {
    this.cursor = svg('line', { class: 'cong-cursor', y1: M.t, y2: M.t + OCC_H + GAP + ENT_H, visibility: 'hidden' });
    this.band = svg('rect', { class: 'cong-band', y: M.t, height: OCC_H + GAP + ENT_H, visibility: 'hidden' });
    this.body = svg('g', {});
    this.el = svg('svg', { class: 'cong-series', viewBox: `0 0 ${W} ${H}`, role: 'img', 'aria-label': 'Occupancy and entry counts of the selected volume', 'data-testid': 'cong-series' }, this.band, this.body, this.cursor);
    this.el.addEventListener('click', (e) => {
      const t = this.timeAtClient(e.clientX);
      if (t !== null) onSeek(t);
    });
  }

  private x(t: number): number {
    const p = this.model!.periods;
    return M.l + ((t - p.t0) / (p.t1 - p.t0)) * (W - M.l - M.r);
  }

  private timeAtClient(clientX: number): number | null {
    if (!this.model) return null;
    const r = this.el.getBoundingClientRect();
    const px = ((clientX - r.left) / r.width) * W;
    const p = this.model.periods;
    const t = p.t0 + ((px - M.l) / (W - M.l - M.r)) * (p.t1 - p.t0);
    return Math.min(p.t1, Math.max(p.t0, t));
  }

  /** Draws a volume's series (null: empty). */
  set(model: CongestionModel | null, volume: Volume | null): void {
    this.model = model;
    this.volume = volume;
    delete this.el.dataset.occupancy;
    delete this.el.dataset.entries;
    this.el.dataset.volume = volume?.id ?? '';
    if (!model || !volume || model.periods.steps === 0) {
      mount(this.body);
      this.cursor.setAttribute('visibility', 'hidden');
      this.band.setAttribute('visibility', 'hidden');
      return;
    }
    const p = model.periods;
    const occ = volume.occupancy.dense(p.steps);
    const ent = volume.entries.dense(model.entryWindows);
    // What is drawn, for scripts and the browser test: the dense series.
    this.el.dataset.occupancy = Array.from(occ).join(',');
    this.el.dataset.entries = Array.from(ent).join(',');
    const top = Math.max(1, volume.occupancy.max(), volume.peak ?? 0, volume.sustained ?? 0) * 1.1;
    const y = (v: number) => M.t + OCC_H - (v / top) * OCC_H;
    let d = '';
    for (let k = 0; k < p.steps; k++) {
      const x0 = this.x(periodStart(p, k)).toFixed(1);
      const x1 = this.x(Math.min(periodStart(p, k + 1), p.t1)).toFixed(1);
      const yy = y(occ[k]!).toFixed(1);
      d += `${k === 0 ? 'M' : 'L'}${x0},${yy}H${x1}`;
    }
    const entTop = Math.max(1, volume.entries.max());
    const e0 = M.t + OCC_H + GAP;
    const ey = (v: number) => e0 + ENT_H - (v / entTop) * ENT_H;
    let de = '';
    for (let j = 0; j < model.entryWindows; j++) {
      const x0 = this.x(p.t0 + j * model.entryStep).toFixed(1);
      const x1 = this.x(Math.min(p.t0 + (j + 1) * model.entryStep, p.t1)).toFixed(1);
      de += `${j === 0 ? 'M' : 'L'}${x0},${ey(ent[j]!).toFixed(1)}H${x1}`;
    }
    const thresholdLine = (v: number | null, cls: string, label: string) =>
      v === null
        ? null
        : svg('g', { class: cls, 'data-testid': `cong-series-${cls.replace('cong-', '')}`, 'data-value': v }, svg('line', { x1: M.l, x2: W - M.r, y1: y(v), y2: y(v) }), svg('text', { x: W - M.r - 2, y: y(v) - 2, 'text-anchor': 'end' }, `${label} ${v}`));
    const axisText = (x: number, yy: number, text: string, anchor = 'start') => svg('text', { x, y: yy, 'text-anchor': anchor, class: 'cong-axis' }, text);
    mount(
      this.body,
      svg('line', { class: 'cong-axis-line', x1: M.l, x2: W - M.r, y1: M.t + OCC_H, y2: M.t + OCC_H }),
      svg('line', { class: 'cong-axis-line', x1: M.l, x2: W - M.r, y1: e0 + ENT_H, y2: e0 + ENT_H }),
      axisText(M.l - 3, y(top / 1.1) + 4, String(Math.round(top / 1.1)), 'end'),
      axisText(M.l - 3, M.t + OCC_H, '0', 'end'),
      axisText(M.l - 3, e0 + 8, String(entTop), 'end'),
      axisText(M.l, e0 - 3, `entries / ${Math.round(model.entryWindow / 60)} min, every ${Math.round(model.entryStep / 60)} min`),
      axisText(M.l, H - 1, formatUtcTime(p.t0)),
      axisText(W - M.r, H - 1, formatUtcTime(periodEnd(p, p.steps - 1)), 'end'),
      svg('path', { class: 'cong-occ', d }),
      svg('path', { class: 'cong-ent', d: de }),
      thresholdLine(volume.sustained, 'cong-sustained', 'sustained'),
      thresholdLine(volume.peak, 'cong-peak', 'peak'),
    );
  }

  /** The cursor at instant t (hidden when NaN or outside the result's window), and the period k. */
  setCursor(t: number, k: number): void {
    this.el.dataset.cursor = Number.isFinite(t) ? String(t) : '';
    this.el.dataset.k = String(k);
    if (!this.model || !this.volume || !Number.isFinite(t) || t < this.model.periods.t0 || t > this.model.periods.t1) {
      this.cursor.setAttribute('visibility', 'hidden');
      return;
    }
    const x = this.x(t).toFixed(2);
    this.cursor.setAttribute('x1', x);
    this.cursor.setAttribute('x2', x);
    this.cursor.setAttribute('visibility', 'visible');
  }

  /** The time window as a band (null hides it). */
  setWindow(w: { start: number; end: number } | null): void {
    if (!this.model || !this.volume || !w) {
      this.band.setAttribute('visibility', 'hidden');
      return;
    }
    const p = this.model.periods;
    const a = this.x(Math.max(p.t0, w.start));
    const b = this.x(Math.min(p.t1, w.end));
    if (!(b > a)) {
      this.band.setAttribute('visibility', 'hidden');
      return;
    }
    this.band.setAttribute('x', a.toFixed(1));
    this.band.setAttribute('width', (b - a).toFixed(1));
    this.band.setAttribute('visibility', 'visible');
  }
}
