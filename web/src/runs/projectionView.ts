// The projection scatter: one point per run at its projected coordinates (equal scales on both axes),
// coloured by a metric (legend), selected runs ringed, runs outside the parallel-coordinate filter dimmed.
// Drag = rectangle brush, Alt-drag or the lasso mode = lasso; Shift adds to the selection; click a point =
// select its run; Escape clears. Hover shows the run and its metric.

import { cssContext, fitCanvas, h, mount, sectionHead } from '../lib/dom';
import type { ColorScale } from './colorScale';
import { linearTicks, renderLegend } from '../lib/legend';
import { brushHits, fitPoints, nearest, normRect, overlapGroups, type Fit, type Pt } from './geometry';

export interface ScatterPoint {
  id: string;
  x: number;
  y: number;
  value: number;
  label: string;
}

export interface ProjectionViewOptions {
  onSelect(ids: string[], add: boolean): void;
  /** The stale mark's one-click recompute. */
  onRecompute?(): void;
}

const RADIUS = 4;

export class ProjectionView {
  readonly root: HTMLElement;
  readonly canvas: HTMLCanvasElement;
  private readonly plot: HTMLElement;
  private readonly tooltip: HTMLElement;
  private readonly legend: HTMLElement;
  private readonly message: HTMLElement;
  private readonly lassoToggle: HTMLInputElement;
  private readonly staleBox: HTMLElement;
  private readonly staleText: HTMLElement;
  private points: ScatterPoint[] = [];
  private px: Pt[] = [];
  private fit: Fit | null = null;
  private scale: ColorScale | null = null;
  private selected = new Set<string>();
  private highlight: Set<string> | null = null;
  private hover = -1;
  private width = 0;
  private height = 0;
  private drag: { start: Pt; path: Pt[]; lasso: boolean; add: boolean; moved: boolean } | null = null;
  private raf = 0;

  constructor(
    private readonly opts: ProjectionViewOptions,
    controls: HTMLElement,
  ) {
    this.canvas = h('canvas', { class: 'scatter-canvas', 'data-testid': 'projection-canvas' });
    this.tooltip = h('div', { class: 'scatter-tip', hidden: true, role: 'status' });
    this.message = h('div', { class: 'scatter-message muted' }, 'No projection yet.');
    this.plot = h(
      'div',
      {
        class: 'scatter-plot',
        tabindex: 0,
        role: 'application',
        'aria-label': 'Projection of the runs; drag to brush runs, Alt-drag for a lasso, Shift to add, Escape to clear',
        'data-testid': 'projection',
        'data-state': 'empty',
      },
      this.canvas,
      this.tooltip,
      this.message,
    );
    this.legend = h('div', { class: 'scatter-legend', 'data-testid': 'projection-legend' });
    this.lassoToggle = h('input', { type: 'checkbox', 'data-testid': 'lasso-mode' });
    this.staleText = h('span', { class: 'small muted' });
    this.staleBox = h(
      'div',
      { class: 'stale-line', 'data-testid': 'projection-stale', hidden: true, role: 'status' },
      h('span', { class: 'stale-mark' }, 'stale'),
      this.staleText,
      h('button', { type: 'button', class: 'link-button', 'data-testid': 'projection-recompute', onclick: () => this.opts.onRecompute?.() }, 'Recompute'),
    );
    this.root = h(
      'section',
      { class: 'runs-panel projection-panel', 'aria-label': 'Projection' },
      sectionHead('Projection', controls),
      this.staleBox,
      this.plot,
      h(
        'div',
        { class: 'scatter-foot' },
        this.legend,
        h('label', { class: 'check small' }, this.lassoToggle, ' lasso'),
      ),
    );
    new ResizeObserver(() => this.resize()).observe(this.plot);
    this.plot.addEventListener('pointerdown', (e) => this.onDown(e));
    this.plot.addEventListener('pointermove', (e) => this.onMove(e));
    this.plot.addEventListener('pointerup', (e) => this.onUp(e));
    this.plot.addEventListener('pointercancel', () => {
      this.drag = null;
      this.invalidate();
    });
    this.plot.addEventListener('pointerleave', () => {
      if (this.hover >= 0) {
        this.hover = -1;
        this.tooltip.hidden = true;
        this.invalidate();
      }
    });
    this.plot.addEventListener('keydown', (e) => {
      if (e.key === 'Escape') this.opts.onSelect([], false);
      else if (e.key === 'a' && (e.ctrlKey || e.metaKey)) {
        e.preventDefault();
        this.opts.onSelect(this.points.map((p) => p.id), false);
      }
    });
  }

  setState(state: 'empty' | 'loading' | 'ready' | 'error', message = ''): void {
    this.plot.dataset.state = state;
    this.message.hidden = state === 'ready';
    this.message.textContent = message;
    this.message.classList.toggle('error-text', state === 'error');
  }

  /** Marks the projection stale (its inputs changed since it was made), with why; null clears the mark. */
  setStale(why: string | null): void {
    this.staleBox.hidden = why === null;
    this.staleText.textContent = why === null ? '' : ` ${why} `;
    this.plot.dataset.stale = String(why !== null);
  }

  setPoints(points: ScatterPoint[]): void {
    this.points = points;
    this.plot.dataset.points = String(points.length);
    this.refit();
    this.invalidate();
  }

  setColor(scale: ColorScale | null, label: string, format: (v: number) => string): void {
    this.scale = scale;
    if (scale) {
      const bar = h('div', {});
      renderLegend(bar, { title: label, stops: scale.stops, ticks: linearTicks(scale.lo, scale.hi, 4, format), width: 200, testid: 'projection-legend' });
      mount(this.legend, bar, h('span', { class: 'legend-item' }, h('span', { class: 'legend-dot nan' }), 'no value'));
    } else mount(this.legend);
    this.invalidate();
  }

  setSelection(ids: readonly string[]): void {
    this.selected = new Set(ids);
    this.invalidate();
  }

  setHighlight(ids: Set<string> | null): void {
    this.highlight = ids;
    this.invalidate();
  }

  /** Client (viewport) coordinates of each point, for the test and keyboard-free checks. */
  clientPoints(): { id: string; x: number; y: number; cx: number; cy: number }[] {
    const r = this.plot.getBoundingClientRect();
    return this.points.map((p, i) => ({ id: p.id, x: p.x, y: p.y, cx: r.left + (this.px[i]?.x ?? NaN), cy: r.top + (this.px[i]?.y ?? NaN) }));
  }

  private resize() {
    ({ width: this.width, height: this.height } = fitCanvas(this.canvas, this.plot));
    this.refit();
    this.draw();
  }

  private refit() {
    this.fit = fitPoints(
      this.points.map((p) => [p.x, p.y] as const),
      this.width,
      this.height,
      14,
    );
    this.px = this.points.map((p) => this.fit!.toPx(p.x, p.y));
  }

  private local(e: PointerEvent): Pt {
    const r = this.plot.getBoundingClientRect();
    return { x: e.clientX - r.left, y: e.clientY - r.top };
  }

  private onDown(e: PointerEvent) {
    if (e.button !== 0 || this.points.length === 0) return;
    this.plot.focus({ preventScroll: true });
    this.plot.setPointerCapture(e.pointerId);
    const p = this.local(e);
    this.drag = { start: p, path: [p], lasso: e.altKey || this.lassoToggle.checked, add: e.shiftKey || e.ctrlKey || e.metaKey, moved: false };
  }

  private onMove(e: PointerEvent) {
    const p = this.local(e);
    if (this.drag) {
      const d = this.drag;
      if (Math.hypot(p.x - d.start.x, p.y - d.start.y) > 3) d.moved = true;
      const last = d.path[d.path.length - 1]!;
      if (Math.hypot(p.x - last.x, p.y - last.y) >= 2) d.path.push(p);
      this.invalidate();
      return;
    }
    const i = nearest(this.px, p, RADIUS + 4);
    if (i !== this.hover) {
      this.hover = i;
      this.invalidate();
    }
    if (i >= 0) {
      const pt = this.points[i]!;
      this.tooltip.hidden = false;
      this.tooltip.textContent = pt.label;
      this.tooltip.style.left = `${Math.min(p.x + 12, Math.max(0, this.width - 200))}px`;
      this.tooltip.style.top = `${Math.max(0, p.y - 28)}px`;
    } else this.tooltip.hidden = true;
  }

  private onUp(e: PointerEvent) {
    const d = this.drag;
    this.drag = null;
    if (!d) return;
    const end = this.local(e);
    if (!d.moved) {
      const i = nearest(this.px, end, RADIUS + 4);
      if (i >= 0) {
        const id = this.points[i]!.id;
        if (d.add && this.selected.has(id)) this.opts.onSelect([...this.selected].filter((s) => s !== id), false);
        else this.opts.onSelect([id], d.add);
      } else if (!d.add) this.opts.onSelect([], false);
      this.invalidate();
      return;
    }
    d.path.push(end);
    const hits = d.lasso ? brushHits(this.px, { lasso: d.path }) : brushHits(this.px, { rect: normRect(d.start, end) });
    this.opts.onSelect(
      hits.map((i) => this.points[i]!.id),
      d.add,
    );
    this.invalidate();
  }

  private invalidate() {
    if (this.raf) return;
    this.raf = requestAnimationFrame(() => {
      this.raf = 0;
      this.draw();
    });
  }

  private draw() {
    if (this.width === 0) return;
    const ctx = cssContext(this.canvas, this.width, this.height);
    if (!ctx) return;
    ctx.fillStyle = '#0b0f14';
    ctx.fillRect(0, 0, this.width, this.height);
    const order: number[] = [];
    const front: number[] = [];
    this.points.forEach((p, i) => (this.selected.has(p.id) ? front : order).push(i));
    const drawPoint = (i: number, isFront: boolean) => {
      const p = this.points[i]!;
      const q = this.px[i]!;
      if (!Number.isFinite(q.x) || !Number.isFinite(q.y)) return;
      const dim = this.highlight !== null && !this.highlight.has(p.id);
      ctx.globalAlpha = dim ? 0.18 : 0.92;
      ctx.beginPath();
      ctx.arc(q.x, q.y, isFront ? RADIUS + 1 : RADIUS, 0, Math.PI * 2);
      ctx.fillStyle = this.scale ? this.scale.color(p.value) : '#9aa5b3';
      ctx.fill();
      // A light rim: the dark end of viridis/inferno would otherwise vanish into the black plot.
      if (!isFront) {
        ctx.lineWidth = 1;
        ctx.strokeStyle = dim ? 'rgba(200, 210, 225, 0.25)' : 'rgba(220, 228, 240, 0.7)';
        ctx.stroke();
      }
      if (isFront) {
        ctx.globalAlpha = 1;
        ctx.lineWidth = 1.6;
        ctx.strokeStyle = '#ffffff';
        ctx.stroke();
      }
    };
    for (const i of order) drawPoint(i, false);
    for (const i of front) drawPoint(i, true);
    ctx.globalAlpha = 1;
    // Runs drawn on top of one another (identical results project to one place): a ring and their count.
    const stacks = overlapGroups(this.px, 1);
    this.root.dataset.overlaps = String(stacks.length);
    this.root.dataset.overlapRuns = stacks.map((g) => g.map((i) => this.points[i]!.id).join('+')).join(' ');
    ctx.font = '10px ui-monospace, monospace';
    for (const g of stacks) {
      const q = this.px[g[0]!]!;
      ctx.beginPath();
      ctx.arc(q.x, q.y, RADIUS + 3, 0, Math.PI * 2);
      ctx.strokeStyle = '#f5f7fa';
      ctx.lineWidth = 1;
      ctx.setLineDash([2, 2]);
      ctx.stroke();
      ctx.setLineDash([]);
      ctx.fillStyle = '#f5f7fa';
      ctx.fillText(`×${g.length}`, q.x + RADIUS + 4, q.y - RADIUS - 2);
    }
    if (this.hover >= 0 && this.px[this.hover]) {
      const q = this.px[this.hover]!;
      ctx.beginPath();
      ctx.arc(q.x, q.y, RADIUS + 4, 0, Math.PI * 2);
      ctx.strokeStyle = '#ff8a1f';
      ctx.lineWidth = 1.5;
      ctx.stroke();
    }
    const d = this.drag;
    if (d && d.moved) {
      ctx.strokeStyle = '#ff8a1f';
      ctx.fillStyle = 'rgba(255, 138, 31, 0.10)';
      ctx.lineWidth = 1;
      ctx.setLineDash([4, 3]);
      ctx.beginPath();
      if (d.lasso) {
        d.path.forEach((p, k) => (k ? ctx.lineTo(p.x, p.y) : ctx.moveTo(p.x, p.y)));
        ctx.closePath();
      } else {
        const last = d.path[d.path.length - 1]!;
        const r = normRect(d.start, last);
        ctx.rect(r.x0, r.y0, r.x1 - r.x0, r.y1 - r.y0);
      }
      ctx.fill();
      ctx.stroke();
      ctx.setLineDash([]);
    }
  }
}
