// Parallel coordinates of the runs: one axis per varying parameter and per metric, one line per run
// coloured like the projection. Drag along an axis to brush an interval (runs outside every brush are
// dimmed everywhere); click an axis or press Escape/Delete on it to clear its brush. Selected runs are
// drawn on top, thick and opaque.

import { h, mount, sectionHead, svg } from '../lib/dom';
import type { ColorScale } from './colorScale';
import { formatNumber } from './metrics';
import { axisX, valueAt, yOf, type PcAxis } from './parcoordsScale';

export interface PcRow {
  id: string;
  values: Map<string, number>;
  colorValue: number;
}

export interface ParallelCoordsOptions {
  onBrush(brushes: Map<string, [number, number]>): void;
  onSelect(ids: string[]): void;
}

const TOP = 26;
const BOTTOM_PAD = 30;
const PAD_X = 48;

export class ParallelCoords {
  readonly root: HTMLElement;
  private readonly svgEl: SVGSVGElement;
  private readonly meta: HTMLElement;
  private axes: PcAxis[] = [];
  private rows: PcRow[] = [];
  private brushes = new Map<string, [number, number]>();
  private selected = new Set<string>();
  private scale: ColorScale | null = null;
  private width = 0;
  private height = 0;

  constructor(private readonly opts: ParallelCoordsOptions) {
    this.svgEl = svg('svg', { class: 'pc-svg', 'data-testid': 'parcoords', role: 'group', 'aria-label': 'Parallel coordinates of parameters and metrics' });
    this.meta = h('span', { class: 'section-meta', 'data-testid': 'parcoords-meta' });
    const selectFiltered = h('button', { class: 'btn btn-small', type: 'button', onclick: () => this.selectFiltered() }, 'Select filtered');
    const clear = h('button', { class: 'btn btn-small', type: 'button', onclick: () => this.clearBrushes() }, 'Clear filters');
    this.root = h(
      'section',
      { class: 'runs-panel pc-panel', 'aria-label': 'Parallel coordinates' },
      sectionHead('Parameters and results', this.meta, selectFiltered, clear),
      h('div', { class: 'pc-plot' }, this.svgEl),
      h('p', { class: 'hint' }, 'Drag along an axis to filter runs to an interval; click the axis (or Escape on it) to clear.'),
    );
    new ResizeObserver(() => {
      const r = this.svgEl.getBoundingClientRect();
      if (Math.round(r.width) !== this.width || Math.round(r.height) !== this.height) {
        this.width = Math.round(r.width);
        this.height = Math.round(r.height);
        this.render();
      }
    }).observe(this.svgEl);
  }

  setData(axes: PcAxis[], rows: PcRow[]): void {
    this.axes = axes;
    this.rows = rows;
    for (const k of [...this.brushes.keys()]) if (!axes.some((a) => a.key === k)) this.brushes.delete(k);
    this.render();
  }

  setColor(scale: ColorScale | null): void {
    this.scale = scale;
    this.render();
  }

  setSelection(ids: readonly string[]): void {
    this.selected = new Set(ids);
    this.render();
  }

  /** Sets the brushes (from the URL); axes not shown are dropped. Does not emit. */
  setBrushes(b: readonly [string, [number, number]][]): void {
    this.brushes = new Map(b.filter(([k]) => this.axes.some((a) => a.key === k)));
    this.render();
  }

  get brushState(): Map<string, [number, number]> {
    return this.brushes;
  }

  /** Ids of the rows passing every brush (all when none). */
  filtered(): string[] {
    return this.rows.filter((r) => this.passes(r)).map((r) => r.id);
  }

  private passes(r: PcRow): boolean {
    for (const [k, [a, b]] of this.brushes) {
      const v = r.values.get(k);
      if (v === undefined || !(v >= a && v <= b)) return false;
    }
    return true;
  }

  private selectFiltered() {
    if (this.brushes.size) this.opts.onSelect(this.filtered());
  }

  private clearBrushes() {
    this.brushes.clear();
    this.opts.onBrush(new Map());
    this.render();
  }

  private render() {
    const w = this.width;
    const hgt = this.height;
    const n = this.axes.length;
    this.meta.textContent = n ? `${n} axes · ${this.brushes.size ? `${this.filtered().length} of ${this.rows.length} runs in filter` : `${this.rows.length} runs`}` : '';
    if (w === 0 || hgt === 0 || n === 0) {
      mount(this.svgEl);
      return;
    }
    const bottom = hgt - BOTTOM_PAD;
    const xs = this.axes.map((_, i) => axisX(i, n, w, PAD_X));
    const lineOf = (r: PcRow) => this.axes.map((a, i) => `${xs[i]!.toFixed(1)},${yOf(r.values.get(a.key) ?? NaN, a, TOP, bottom, bottom + 12).toFixed(1)}`).join(' ');
    const back = svg('g', { class: 'pc-lines' });
    const front = svg('g', { class: 'pc-lines selected' });
    const brushed = this.brushes.size > 0;
    for (const r of this.rows) {
      const sel = this.selected.has(r.id);
      const pass = !brushed || this.passes(r);
      const color = !pass ? '#3a4350' : this.scale ? this.scale.color(r.colorValue) : '#9aa5b3';
      const line = svg('polyline', {
        points: lineOf(r),
        stroke: color,
        'stroke-width': sel ? 2.2 : 1,
        'stroke-opacity': sel ? 1 : pass ? 0.55 : 0.25,
        fill: 'none',
        'data-run': r.id,
      });
      (sel ? front : back).append(line);
    }
    const axesG = svg('g', { class: 'pc-axes' });
    this.axes.forEach((a, i) => {
      const x = xs[i]!;
      const g = svg('g', { class: 'pc-axis', tabindex: 0, role: 'slider', 'aria-label': `${a.label}: drag to filter`, 'data-axis': a.key });
      g.append(svg('line', { x1: x, x2: x, y1: TOP, y2: bottom, class: 'pc-axis-line' }));
      g.append(svg('text', { x, y: TOP - 8, class: 'pc-label', 'text-anchor': 'middle' }, a.label));
      g.append(svg('text', { x: x + 4, y: TOP + 9, class: 'pc-tick' }, formatNumber(a.hi)));
      g.append(svg('text', { x: x + 4, y: bottom, class: 'pc-tick' }, formatNumber(a.lo)));
      g.append(svg('text', { x, y: bottom + 24, class: 'pc-tick', 'text-anchor': 'middle' }, 'n/a'));
      const b = this.brushes.get(a.key);
      if (b) {
        const y0 = yOf(b[1], a, TOP, bottom);
        const y1 = yOf(b[0], a, TOP, bottom);
        g.append(svg('rect', { x: x - 7, y: y0, width: 14, height: Math.max(2, y1 - y0), class: 'pc-brush' }));
      }
      const hit = svg('rect', { x: x - 12, y: TOP - 4, width: 24, height: bottom - TOP + 8, class: 'pc-hit' });
      g.append(hit);
      this.bindAxis(g, a, bottom);
      axesG.append(g);
    });
    mount(this.svgEl, back, front, axesG);
  }

  private bindAxis(g: SVGGElement, a: PcAxis, bottom: number) {
    let startY = 0;
    let moved = false;
    let dragging = false;
    const yLocal = (e: PointerEvent) => e.clientY - this.svgEl.getBoundingClientRect().top;
    g.addEventListener('pointerdown', (e) => {
      if (e.button !== 0) return;
      dragging = true;
      moved = false;
      startY = yLocal(e);
      g.setPointerCapture(e.pointerId);
      e.preventDefault();
    });
    g.addEventListener('pointermove', (e) => {
      if (!dragging) return;
      const y = yLocal(e);
      if (Math.abs(y - startY) < 3 && !moved) return;
      moved = true;
      const v0 = valueAt(startY, a, TOP, bottom);
      const v1 = valueAt(y, a, TOP, bottom);
      this.brushes.set(a.key, [Math.min(v0, v1), Math.max(v0, v1)]);
      // Only the brush rectangle moves while dragging (re-rendering would drop the pointer capture).
      let live = g.querySelector<SVGRectElement>('.pc-brush');
      if (!live) {
        live = svg('rect', { class: 'pc-brush', x: Number(g.querySelector('line')?.getAttribute('x1') ?? 0) - 7, width: 14 });
        g.insertBefore(live, g.querySelector('.pc-hit'));
      }
      const ya = Math.max(TOP, Math.min(bottom, Math.min(startY, y)));
      const yb = Math.max(TOP, Math.min(bottom, Math.max(startY, y)));
      live.setAttribute('y', String(ya));
      live.setAttribute('height', String(Math.max(2, yb - ya)));
    });
    const end = () => {
      if (!dragging) return;
      dragging = false;
      if (!moved) this.brushes.delete(a.key);
      this.render();
      this.opts.onBrush(new Map(this.brushes));
    };
    g.addEventListener('pointerup', end);
    g.addEventListener('pointercancel', end);
    g.addEventListener('keydown', (e) => {
      if ((e.key === 'Escape' || e.key === 'Delete' || e.key === 'Backspace') && this.brushes.has(a.key)) {
        this.brushes.delete(a.key);
        this.render();
        this.opts.onBrush(new Map(this.brushes));
      }
    });
  }
}
