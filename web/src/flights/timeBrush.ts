// The time histogram along the bottom, with a brush to pick the time window [t0, t1).
// Drag to select (snapped to bins), drag inside to move, drag an edge to resize, double-click to clear.
// Keyboard: ←/→ move the window by one bin, Shift+←/→ move its end, Esc clears.
// With the playback clock shown (setCursor), a cursor marks its instant: drag the cursor to scrub, click
// anywhere to jump there (the clock itself lives in clock.ts; this only draws and reports).

import type { TimeHistogram } from '../api/types';
import {
  binInWindow,
  brushDomain,
  coversDomain,
  gridOf,
  hitTest,
  moveWindow,
  resizeWindow,
  timeToX,
  windowFromDrag,
  xToTime,
  type DragMode,
  type Span,
} from './brush';
import { h, svg, mount } from '../lib/dom';
import { formatCompact, formatInt, formatUtc, formatUtcTime, formatWindow, formatDuration } from '../lib/format';

const AXIS_H = 16;
const TOP_PAD = 6;

const TICK_STEPS = [60, 300, 900, 1800, 3600, 7200, 10800, 21600, 43200, 86400, 172800, 604800, 2592000];

export interface TimeBrushEvents {
  /** The user committed a window (null clears it). */
  onWindow(w: Span | null): void;
  /** The user moved the time cursor to t (a click, or each step of a drag on the cursor). */
  onCursor?(t: number): void;
}

/** How close (px) to the cursor a press grabs it rather than starting a window. */
const CURSOR_GRAB_PX = 5;

export class TimeBrush {
  private readonly svgEl: SVGSVGElement;
  private readonly readout: HTMLElement;
  private readonly tooltip: HTMLElement;
  private readonly plot: HTMLElement;
  private hist: TimeHistogram | null = null;
  private domain: Span | null = null;
  private window: Span | null = null;
  private width = 0;
  private height = 0;
  private drag: { mode: DragMode | 'cursor'; startT: number; startWin: Span | null; moved: boolean } | null = null;
  private cursor: number | null = null;
  private cursorEl: SVGGElement | null = null;
  private state: 'empty' | 'loading' | 'ready' | 'error' = 'empty';
  private message = 'Pick a data set to see its traffic over time.';

  constructor(root: HTMLElement, private readonly events: TimeBrushEvents) {
    this.readout = h('span', { class: 'brush-readout', id: 'brush-readout', 'data-testid': 'time-window' });
    const clear = h('button', { class: 'link-button', type: 'button', onclick: () => this.commit(null) }, 'Clear');
    clear.setAttribute('data-testid', 'time-clear');
    root.append(
      h(
        'div',
        { class: 'brush-head' },
        h('span', { class: 'section-title' }, 'Time (UTC)'),
        this.readout,
        clear,
        h('span', { class: 'brush-hint' }, 'drag to select · double-click to clear · ←/→ move'),
      ),
    );
    this.plot = h('div', {
      class: 'brush-plot',
      tabindex: 0,
      role: 'group',
      'aria-label': 'Time histogram and time window brush',
      'aria-describedby': 'brush-readout',
      'data-testid': 'time-brush',
      'data-param': 't0 t1',
    });
    this.svgEl = svg('svg', { class: 'brush-svg', 'aria-hidden': 'true' });
    this.tooltip = h('div', { class: 'brush-tooltip', hidden: true });
    this.plot.append(this.svgEl, this.tooltip);
    root.append(this.plot);

    new ResizeObserver(() => this.resize()).observe(this.plot);
    this.plot.addEventListener('pointerdown', (e) => this.onDown(e));
    this.plot.addEventListener('pointermove', (e) => this.onMove(e));
    this.plot.addEventListener('pointerup', (e) => this.onUp(e));
    this.plot.addEventListener('pointercancel', () => this.cancelDrag());
    this.plot.addEventListener('pointerleave', () => (this.tooltip.hidden = true));
    this.plot.addEventListener('dblclick', (e) => {
      e.preventDefault();
      this.commit(null);
    });
    this.plot.addEventListener('keydown', (e) => this.onKey(e));
    this.updateReadout();
  }

  /** The full-time histogram (filtered by everything but time) and the data set's time range. */
  setData(hist: TimeHistogram, tMin: number, tMax: number): void {
    this.hist = hist;
    this.domain = brushDomain(tMin, tMax, hist);
    this.state = 'ready';
    this.tooltip.hidden = true;
    this.render();
  }

  setLoading(): void {
    if (this.state !== 'ready') this.state = 'loading';
    this.plot.dataset.state = 'loading';
  }

  setMessage(state: 'empty' | 'error', message: string): void {
    this.state = state;
    this.message = message;
    this.hist = null;
    this.tooltip.hidden = true;
    this.render();
  }

  /** The window as the app holds it (from the URL or a reset); does not emit. */
  setWindow(w: Span | null): void {
    this.window = w;
    this.render();
  }

  private resize() {
    const r = this.plot.getBoundingClientRect();
    this.width = Math.max(0, Math.floor(r.width));
    this.height = Math.max(0, Math.floor(r.height));
    this.render();
  }

  private plotH() {
    return Math.max(0, this.height - AXIS_H - TOP_PAD);
  }

  private localX(e: PointerEvent | MouseEvent) {
    return e.clientX - this.plot.getBoundingClientRect().left;
  }

  /** Shows the clock's instant as a cursor (null hides it). Moves only the cursor, not the whole plot. */
  setCursor(t: number | null): void {
    this.cursor = t !== null && Number.isFinite(t) ? t : null;
    this.plot.dataset.cursor = this.cursor === null ? '' : String(this.cursor);
    this.placeCursor();
  }

  private cursorX(): number | null {
    return this.cursor === null || !this.domain ? null : timeToX(this.cursor, this.domain, this.width);
  }

  private placeCursor() {
    const el = this.cursorEl;
    if (!el) return;
    const x = this.cursorX();
    el.style.display = x === null ? 'none' : '';
    if (x !== null) el.setAttribute('transform', `translate(${x.toFixed(2)},0)`);
  }

  private winPx(w: Span | null) {
    if (!w || !this.domain) return null;
    return { x0: timeToX(w.start, this.domain, this.width), x1: timeToX(w.end, this.domain, this.width) };
  }

  private onDown(e: PointerEvent) {
    if (e.button !== 0 || !this.domain || !this.hist) return;
    const x = this.localX(e);
    const cx = this.cursorX();
    const mode = this.events.onCursor && cx !== null && Math.abs(x - cx) <= CURSOR_GRAB_PX ? 'cursor' : hitTest(x, this.winPx(this.window));
    this.drag = { mode, startT: xToTime(x, this.domain, this.width), startWin: this.window, moved: false };
    this.plot.setPointerCapture(e.pointerId);
    this.plot.classList.add('dragging');
    e.preventDefault();
    this.plot.focus({ preventScroll: true });
  }

  private onMove(e: PointerEvent) {
    if (!this.domain || !this.hist) return;
    const x = this.localX(e);
    const t = xToTime(x, this.domain, this.width);
    const grid = gridOf(this.hist);
    if (!this.drag) {
      this.hover(x, t);
      const cx = this.cursorX();
      const onCursor = this.events.onCursor && cx !== null && Math.abs(x - cx) <= CURSOR_GRAB_PX;
      const mode = hitTest(x, this.winPx(this.window));
      this.plot.style.cursor = onCursor || mode === 'start' || mode === 'end' ? 'ew-resize' : mode === 'move' ? 'grab' : 'crosshair';
      return;
    }
    this.tooltip.hidden = true;
    const d = this.drag;
    if (d.mode === 'cursor') {
      d.moved = true;
      this.events.onCursor?.(t);
      return;
    }
    if (!d.moved && Math.abs(t - d.startT) < grid.step / 4) return;
    d.moved = true;
    if (d.mode === 'new' || !d.startWin) this.window = windowFromDrag(d.startT, t, this.domain, grid);
    else if (d.mode === 'move') this.window = moveWindow(d.startWin, t - d.startT, this.domain, grid);
    else this.window = resizeWindow(d.startWin, d.mode, t, this.domain, grid);
    this.render();
  }

  private onUp(e: PointerEvent) {
    const d = this.drag;
    if (!d) return;
    this.drag = null;
    this.plot.classList.remove('dragging');
    if (this.plot.hasPointerCapture(e.pointerId)) this.plot.releasePointerCapture(e.pointerId);
    // A plain click changes no window (it would otherwise fire a query before every double-click); with
    // the cursor shown it jumps the clock there.
    if (d.mode === 'cursor') return;
    if (d.moved) this.commit(this.window);
    else if (this.events.onCursor && this.cursor !== null) this.events.onCursor(d.startT);
  }

  private cancelDrag() {
    if (!this.drag) return;
    if (this.drag.mode === 'cursor') {
      this.drag = null;
      this.plot.classList.remove('dragging');
      return;
    }
    this.window = this.drag.startWin;
    this.drag = null;
    this.plot.classList.remove('dragging');
    this.render();
  }

  private onKey(e: KeyboardEvent) {
    if (!this.domain || !this.hist) return;
    const grid = gridOf(this.hist);
    if (e.key === 'Escape' || e.key === 'Delete' || e.key === 'Backspace') {
      if (this.window) {
        e.preventDefault();
        this.commit(null);
      }
      return;
    }
    if (e.key !== 'ArrowLeft' && e.key !== 'ArrowRight') return;
    e.preventDefault();
    const dir = e.key === 'ArrowLeft' ? -1 : 1;
    const w = this.window ?? windowFromDrag(this.domain.start, this.domain.start, this.domain, grid);
    const next = e.shiftKey
      ? resizeWindow(w, 'end', w.end + dir * grid.step, this.domain, grid)
      : this.window
        ? moveWindow(w, dir * grid.step, this.domain, grid)
        : w;
    this.commit(next);
  }

  private commit(w: Span | null) {
    if (w && this.domain && coversDomain(w, this.domain)) w = null;
    this.window = w;
    this.render();
    this.events.onWindow(w);
  }

  private hover(x: number, t: number) {
    const hist = this.hist;
    if (!hist) return;
    const i = Math.floor((t - hist.t0) / hist.bin_seconds);
    if (i < 0 || i >= hist.counts.length) {
      this.tooltip.hidden = true;
      return;
    }
    const b0 = hist.t0 + i * hist.bin_seconds;
    this.tooltip.textContent = `${formatUtc(b0)}–${formatUtcTime(b0 + hist.bin_seconds)} · ${formatInt(hist.counts[i])} points`;
    this.tooltip.hidden = false;
    const tw = this.tooltip.offsetWidth;
    this.tooltip.style.left = `${Math.min(Math.max(0, x - tw / 2), this.width - tw)}px`;
  }

  private updateReadout() {
    const w = this.window;
    this.readout.textContent = w ? `${formatWindow(w.start, w.end)} · ${formatDuration(w.end - w.start)}` : 'All times';
    this.plot.dataset.t0 = w ? String(w.start) : '';
    this.plot.dataset.t1 = w ? String(w.end) : '';
  }

  private render() {
    this.updateReadout();
    this.plot.dataset.state = this.state;
    const W = this.width;
    const H = this.height;
    this.svgEl.setAttribute('viewBox', `0 0 ${W} ${H}`);
    this.svgEl.setAttribute('width', String(W));
    this.svgEl.setAttribute('height', String(H));
    const hist = this.hist;
    const d = this.domain;
    if (!hist || !d || W === 0 || H === 0) {
      this.cursorEl = null;
      mount(this.svgEl, svg('text', { x: W / 2, y: H / 2, class: 'brush-empty', 'text-anchor': 'middle', 'dominant-baseline': 'middle' }, this.state === 'loading' ? 'Loading…' : this.message));
      return;
    }
    const ph = this.plotH();
    const base = TOP_PAD + ph;
    const max = Math.max(0, ...hist.counts);
    const grid = gridOf(hist);
    const bars = svg('g', { class: 'bars' });
    const bw = timeToX(d.start + hist.bin_seconds, d, W) - timeToX(d.start, d, W);
    const gap = bw > 4 ? 1 : 0;
    hist.counts.forEach((c, i) => {
      if (c <= 0) return;
      const x = timeToX(hist.t0 + i * hist.bin_seconds, d, W);
      const bh = Math.max(1, (c / Math.max(1, max)) * ph);
      const inWin = !this.window || binInWindow(i, grid, this.window);
      bars.append(svg('rect', { x: x + gap / 2, y: base - bh, width: Math.max(0.5, bw - gap), height: bh, class: inWin ? 'bar in' : 'bar' }));
    });

    // Axis: ticks at round UTC times.
    const axis = svg('g', { class: 'axis' });
    const span = d.end - d.start;
    const step = TICK_STEPS.find((s) => (span / s) * 80 <= W) ?? TICK_STEPS[TICK_STEPS.length - 1]!;
    const first = Math.ceil(d.start / step) * step;
    axis.append(svg('line', { x1: 0, x2: W, y1: base + 0.5, y2: base + 0.5, class: 'axis-line' }));
    for (let t = first; t <= d.end; t += step) {
      const x = Math.round(timeToX(t, d, W)) + 0.5;
      const label = step >= 86400 || t % 86400 === 0 ? formatUtc(t).slice(0, 10) : formatUtcTime(t);
      axis.append(svg('line', { x1: x, x2: x, y1: base, y2: base + 4, class: 'tick' }));
      // ~6 px per character of the 10 px monospace labels; skip a label the right edge would cut.
      if (x + 3 + label.length * 6.2 <= W) axis.append(svg('text', { x: x + 3, y: base + 13, class: 'tick-label' }, label));
    }
    axis.append(
      max > 0
        ? svg('text', { x: 4, y: TOP_PAD + 9, class: 'tick-label ymax' }, `${formatCompact(max)} pts/bin`)
        : svg('text', { x: W / 2, y: TOP_PAD + ph / 2, class: 'brush-empty', 'text-anchor': 'middle', 'dominant-baseline': 'middle' }, 'No traffic matches the other filters.'),
    );

    const children: SVGElement[] = [bars, axis];
    const wp = this.winPx(this.window);
    if (wp) {
      children.push(
        svg('rect', { x: 0, y: TOP_PAD, width: Math.max(0, wp.x0), height: ph, class: 'shade' }),
        svg('rect', { x: wp.x1, y: TOP_PAD, width: Math.max(0, W - wp.x1), height: ph, class: 'shade' }),
        svg('rect', { x: wp.x0, y: TOP_PAD, width: Math.max(1, wp.x1 - wp.x0), height: ph, class: 'selection' }),
        svg('rect', { x: wp.x0 - 2, y: TOP_PAD + ph / 2 - 10, width: 4, height: 20, rx: 1.5, class: 'handle' }),
        svg('rect', { x: wp.x1 - 2, y: TOP_PAD + ph / 2 - 10, width: 4, height: 20, rx: 1.5, class: 'handle' }),
      );
    }
    this.cursorEl = svg(
      'g',
      { class: 'cursor', 'data-testid': 'time-cursor' },
      svg('line', { x1: 0, x2: 0, y1: 0, y2: base, class: 'cursor-line' }),
      svg('path', { d: 'M-5,0 L5,0 L0,6 Z', class: 'cursor-head' }),
    );
    children.push(this.cursorEl);
    mount(this.svgEl, ...children);
    this.placeCursor();
  }
}
