// The time histogram along the bottom, with a brush to pick the time window [t0, t1) on a zoomable axis.
// The axis (d3-zoom: wheel or pinch, +/−/0 keys, "zoom to window") goes from the whole data set down to
// MIN_VIEW_SECONDS; the histogram is re-asked for the view (onView) so its bins follow the zoom. Drag to
// select at one-second resolution (never snapped to bins), drag inside to move, drag an edge to resize,
// double-click to clear; t0 and t1 can be typed in ISO 8601 (UTC unless a zone is given).
// Keyboard: ←/→ move the window by a nudge (about 1/100 of the view, brush.ts nudgeStep), Shift+←/→ move
// its end, Alt+←/→ its start, Esc clears.
// With the playback clock shown (setCursor), a cursor marks its instant: drag the cursor to scrub, click
// anywhere to jump there (the clock itself lives in clock.ts; this only draws and reports).

import type { TimeHistogram } from '../api/types';
import { select } from 'd3-selection';
import { zoom, zoomIdentity, type D3ZoomEvent, type ZoomBehavior } from 'd3-zoom';
import { scaleUtc } from 'd3-scale';
import { axisBottom } from 'd3-axis';
import { utcFormat } from 'd3-time-format';
import {
  MIN_VIEW_SECONDS,
  SECOND_GRID,
  brushDomain,
  clampView,
  coversDomain,
  formatIsoUtc,
  hitTest,
  nudgeStep,
  parseIsoUtc,
  zoomView,
  moveWindow,
  resizeWindow,
  timeToX,
  windowFromDrag,
  xToTime,
  type DragMode,
  type Span,
} from './brush';
import { h, svg, mount } from '../lib/dom';
import { debounce } from '../lib/dom';
import { formatCompact, formatInt, formatUtcSeconds, formatDuration } from '../lib/format';

const AXIS_H = 16;
const TOP_PAD = 6;

/** How far a pointer must travel (px) before a press becomes a drag. */
const DRAG_PX = 3;

export interface TimeBrushEvents {
  /** The user committed a window (null clears it). */
  onWindow(w: Span | null): void;
  /** The user moved the time cursor to t (a click, or each step of a drag on the cursor). */
  onCursor?(t: number): void;
  /** The axis settled on a new view (null: the whole data set); its histogram is wanted. */
  onView?(view: Span | null): void;
}

/** How close (px) to the cursor a press grabs it rather than starting a window. */
const CURSOR_GRAB_PX = 5;

export class TimeBrush {
  private readonly svgEl: SVGSVGElement;
  private readonly readout: HTMLElement;
  private readonly tooltip: HTMLElement;
  private readonly plot: HTMLElement;
  private readonly t0Input: HTMLInputElement;
  private readonly t1Input: HTMLInputElement;
  private readonly typedError: HTMLElement;
  /** The window the typed fields were last filled from. */
  private typedFor = '-';
  private readonly zoomBehavior: ZoomBehavior<HTMLElement, unknown>;
  private hist: TimeHistogram | null = null;
  /** The whole data set's time range. */
  private domain: Span | null = null;
  /** The part of it the axis shows (the domain when not zoomed). */
  private view: Span | null = null;
  /** A view asked for before the domain was known (from the URL). */
  private pendingView: Span | null = null;
  private window: Span | null = null;
  private width = 0;
  private height = 0;
  private drag: { mode: DragMode | 'cursor'; startT: number; startX: number; startWin: Span | null; moved: boolean } | null = null;
  /** Touch pointers down on the plot: a second one makes the gesture a pinch (d3-zoom's), not a brush drag. */
  private readonly touches = new Set<number>();
  private cursor: number | null = null;
  private cursorEl: SVGGElement | null = null;
  private state: 'empty' | 'loading' | 'ready' | 'error' = 'empty';
  private message = 'Pick a data set to see its traffic over time.';
  private readonly emitView = debounce(() => this.events.onView?.(this.zoomed() ? this.view : null), 200);

  constructor(root: HTMLElement, private readonly events: TimeBrushEvents) {
    this.readout = h('span', { class: 'brush-readout', id: 'brush-readout', 'data-testid': 'time-window' });
    const clear = h('button', { class: 'link-button', type: 'button', onclick: () => this.commit(null) }, 'Clear');
    clear.setAttribute('data-testid', 'time-clear');
    const zoomWin = h('button', { class: 'link-button', type: 'button', 'data-testid': 'time-zoom-window', title: 'Zoom the axis to the window', onclick: () => this.zoomToWindow() }, 'Zoom to window');
    const zoomAll = h('button', { class: 'link-button', type: 'button', 'data-testid': 'time-zoom-all', title: 'Show the whole data set (0)', onclick: () => this.setView(null) }, 'Whole range');
    const iso = (id: string, label: string) => {
      const el = h('input', { type: 'text', class: 'time-input mono', id, 'data-testid': id, 'aria-label': `${label} (ISO 8601, UTC unless a zone is given)`, placeholder: 'YYYY-MM-DDThh:mm:ssZ', spellcheck: 'false', autocomplete: 'off', 'data-param': id === 'time-t0-input' ? 't0' : 't1' });
      el.addEventListener('keydown', (e) => {
        if (e.key === 'Enter') this.applyTyped();
      });
      // Leaving one field while the other is still empty is not an error yet: the analyst is typing the pair.
      el.addEventListener('change', () => {
        if (this.t0Input.value.trim() !== '' && this.t1Input.value.trim() !== '') this.applyTyped();
      });
      return el;
    };
    this.t0Input = iso('time-t0-input', 'Window start');
    this.t1Input = iso('time-t1-input', 'Window end');
    this.typedError = h('span', { class: 'field-error', 'data-testid': 'time-typed-error', role: 'alert', hidden: true });
    root.append(
      h(
        'div',
        { class: 'brush-head' },
        h('span', { class: 'section-title' }, 'Time (UTC)'),
        this.readout,
        clear,
        h('span', { class: 'time-typed' }, this.t0Input, h('span', { class: 'muted' }, '→'), this.t1Input),
        this.typedError,
        zoomWin,
        zoomAll,
        h('span', { class: 'brush-hint', title: 'Drag to select (one-second resolution) · double-click clears · wheel or pinch zooms the axis, +/−/0 keys too · ←/→ nudge the window, Shift+←/→ its end, Alt+←/→ its start' }, 'wheel or pinch: zoom · ←/→ nudge'),
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

    // d3-zoom drives the axis from the wheel and from two-finger pinches only: a one-finger or mouse drag
    // is the brush's. A trackpad pinch arrives as a wheel event with ctrlKey set (Chromium, Firefox and
    // Safari all send it so), which d3-zoom's wheel delta already scales ×10 like a browser zoom; a touch
    // pinch comes as touch events with two touches, and its first finger's brush drag is cancelled when the
    // second lands (onDown).
    this.zoomBehavior = zoom<HTMLElement, unknown>()
      .filter((e: Event) => e.type === 'wheel' || (e.type.startsWith('touch') && (e as TouchEvent).touches.length >= 2))
      // Touch listeners always: d3-zoom otherwise attaches them only where the page saw touch support when
      // it loaded (navigator.maxTouchPoints), and a touch screen attached later (or an emulated one) would
      // get no pinch.
      .touchable(() => true)
      .on('zoom', (e: D3ZoomEvent<HTMLElement, unknown>) => this.onZoom(e.transform.k, e.transform.x));
    select(this.plot).call(this.zoomBehavior).on('dblclick.zoom', null);
    // At a zoom limit d3-zoom lets the wheel through: it would scroll the page under the analyst's hand.
    this.plot.addEventListener('wheel', (e) => e.preventDefault(), { passive: false });
    // One finger drags the brush, two pinch: the browser must neither scroll nor zoom for either. touch-action
    // (styles.css) says so up front; cancelling the one-finger moves as well keeps the sequence's later moves
    // cancelable (Chromium makes them uncancelable once one went uncancelled), so d3-zoom's own
    // preventDefault in the pinch that follows is not refused with a console warning.
    this.plot.addEventListener('touchmove', (e) => e.cancelable && e.preventDefault(), { passive: false });

    new ResizeObserver(() => this.resize()).observe(this.plot);
    this.plot.addEventListener('pointerdown', (e) => this.onDown(e));
    this.plot.addEventListener('pointermove', (e) => this.onMove(e));
    this.plot.addEventListener('pointerup', (e) => this.onUp(e));
    this.plot.addEventListener('pointercancel', (e) => {
      this.touches.delete(e.pointerId);
      this.cancelDrag();
    });
    this.plot.addEventListener('pointerleave', () => (this.tooltip.hidden = true));
    this.plot.addEventListener('dblclick', (e) => {
      e.preventDefault();
      this.commit(null);
    });
    this.plot.addEventListener('keydown', (e) => this.onKey(e));
    this.updateReadout();
  }

  /**
   * A histogram (filtered by everything but time: of the whole data set, or of the current view) and the
   * data set's time range.
   */
  setData(hist: TimeHistogram, tMin: number, tMax: number): void {
    this.hist = hist;
    const d = brushDomain(tMin, tMax);
    const changed = !this.domain || this.domain.start !== d.start || this.domain.end !== d.end;
    this.domain = d;
    if (changed) {
      this.view = d;
      this.syncZoomExtent();
      if (this.pendingView) {
        const v = this.pendingView;
        this.pendingView = null;
        this.setView(v);
      }
    }
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

  /** The axis's view (null: the whole data set). Emits onView once it settles. */
  setView(v: Span | null): void {
    if (!this.domain || this.width === 0) {
      this.pendingView = v;
      return;
    }
    const d = this.domain;
    const target = v ? clampView({ start: v.start, end: Math.max(v.end, v.start + MIN_VIEW_SECONDS) }, d) : d;
    const k = (d.end - d.start) / (target.end - target.start);
    const x = -k * timeToX(target.start, d, this.width);
    select(this.plot).call(this.zoomBehavior.transform, zoomIdentity.translate(x, 0).scale(k));
  }

  /** The view the axis shows, or null when it shows the whole data set. */
  getView(): Span | null {
    return this.zoomed() ? this.view : null;
  }

  private zoomed(): boolean {
    return !!this.view && !!this.domain && (this.view.start > this.domain.start || this.view.end < this.domain.end);
  }

  private syncZoomExtent() {
    const W = Math.max(1, this.width);
    const H = Math.max(1, this.height);
    const full = this.domain ? this.domain.end - this.domain.start : 1;
    this.zoomBehavior
      .extent([
        [0, 0],
        [W, H],
      ])
      .translateExtent([
        [0, 0],
        [W, H],
      ])
      .scaleExtent([1, Math.max(1, full / MIN_VIEW_SECONDS)]);
  }

  /** A d3-zoom transform (scale k, shift x of the whole-domain axis) → the view. */
  private onZoom(k: number, x: number) {
    const d = this.domain;
    if (!d || this.width === 0) return;
    const start = xToTime(-x / k, d, this.width);
    const end = xToTime((this.width - x) / k, d, this.width);
    this.view = clampView({ start, end }, d);
    this.tooltip.hidden = true;
    this.render();
    this.emitView();
  }

  private zoomToWindow() {
    const w = this.window;
    if (!w) return;
    const pad = (w.end - w.start) * 0.1;
    this.setView({ start: w.start - pad, end: w.end + pad });
  }

  private resize() {
    const r = this.plot.getBoundingClientRect();
    const view = this.getView();
    this.width = Math.max(0, Math.floor(r.width));
    this.height = Math.max(0, Math.floor(r.height));
    this.syncZoomExtent();
    // Keep the same view at the new width (the zoom transform is in pixels).
    if (view || this.pendingView) {
      const v = this.pendingView ?? view;
      this.pendingView = null;
      this.setView(v);
    }
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
    if (this.cursor === null || !this.view) return null;
    const x = timeToX(this.cursor, this.view, this.width);
    return x < -1 || x > this.width + 1 ? null : x;
  }

  private placeCursor() {
    const el = this.cursorEl;
    if (!el) return;
    const x = this.cursorX();
    el.style.display = x === null ? 'none' : '';
    if (x !== null) el.setAttribute('transform', `translate(${x.toFixed(2)},0)`);
  }

  private winPx(w: Span | null) {
    if (!w || !this.view) return null;
    return { x0: timeToX(w.start, this.view, this.width), x1: timeToX(w.end, this.view, this.width) };
  }

  private onDown(e: PointerEvent) {
    if (e.pointerType === 'touch') {
      this.touches.add(e.pointerId);
      if (this.touches.size > 1) {
        // A pinch: the first finger's drag gives the window back, and d3-zoom takes the gesture.
        this.cancelDrag();
        return;
      }
    }
    if (e.button !== 0 || !this.view || !this.hist) return;
    const x = this.localX(e);
    const cx = this.cursorX();
    const mode = this.events.onCursor && cx !== null && Math.abs(x - cx) <= CURSOR_GRAB_PX ? 'cursor' : hitTest(x, this.winPx(this.window));
    this.drag = { mode, startT: xToTime(x, this.view, this.width), startX: x, startWin: this.window, moved: false };
    this.plot.setPointerCapture(e.pointerId);
    this.plot.classList.add('dragging');
    e.preventDefault();
    this.plot.focus({ preventScroll: true });
  }

  private onMove(e: PointerEvent) {
    const d = this.domain;
    const v = this.view;
    if (!d || !v || !this.hist) return;
    const x = this.localX(e);
    const t = xToTime(x, v, this.width);
    if (!this.drag) {
      this.hover(x, t);
      const cx = this.cursorX();
      const onCursor = this.events.onCursor && cx !== null && Math.abs(x - cx) <= CURSOR_GRAB_PX;
      const mode = hitTest(x, this.winPx(this.window));
      this.plot.style.cursor = onCursor || mode === 'start' || mode === 'end' ? 'ew-resize' : mode === 'move' ? 'grab' : 'crosshair';
      return;
    }
    this.tooltip.hidden = true;
    const dr = this.drag;
    if (dr.mode === 'cursor') {
      dr.moved = true;
      this.events.onCursor?.(t);
      return;
    }
    if (!dr.moved && Math.abs(x - dr.startX) < DRAG_PX) return;
    dr.moved = true;
    // Whole seconds, never the histogram's bins.
    if (dr.mode === 'new' || !dr.startWin) this.window = windowFromDrag(dr.startT, t, d, SECOND_GRID);
    else if (dr.mode === 'move') this.window = moveWindow(dr.startWin, t - dr.startT, d, SECOND_GRID);
    else this.window = resizeWindow(dr.startWin, dr.mode, t, d, SECOND_GRID);
    this.render();
  }

  private onUp(e: PointerEvent) {
    this.touches.delete(e.pointerId);
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
    this.plot.classList.remove('dragging');
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
    const d = this.domain;
    const v = this.view;
    if (!d || !v || !this.hist) return;
    if (e.key === 'Escape' || e.key === 'Delete' || e.key === 'Backspace') {
      if (this.window) {
        e.preventDefault();
        this.commit(null);
      }
      return;
    }
    if (e.key === '+' || e.key === '=' || e.key === '-' || e.key === '_') {
      e.preventDefault();
      const at = this.window ? (this.window.start + this.window.end) / 2 : (v.start + v.end) / 2;
      this.setView(zoomView(v, d, at, e.key === '+' || e.key === '=' ? 2 : 0.5));
      return;
    }
    if (e.key === '0') {
      e.preventDefault();
      this.setView(null);
      return;
    }
    if (e.key !== 'ArrowLeft' && e.key !== 'ArrowRight') return;
    e.preventDefault();
    const step = nudgeStep(v);
    const dir = e.key === 'ArrowLeft' ? -1 : 1;
    const w = this.window ?? windowFromDrag(v.start, v.start + 10 * step, d, SECOND_GRID);
    const next = e.shiftKey
      ? resizeWindow(w, 'end', w.end + dir * step, d, SECOND_GRID)
      : e.altKey
        ? resizeWindow(w, 'start', w.start + dir * step, d, SECOND_GRID)
        : this.window
          ? moveWindow(w, dir * step, d, SECOND_GRID)
          : w;
    this.commit(next);
  }

  /** The typed t0/t1: both ISO 8601 and in order, or an inline error and nothing sent. */
  private applyTyped() {
    const a = this.t0Input.value.trim();
    const b = this.t1Input.value.trim();
    if (a === '' && b === '') {
      this.showTypedError(null);
      if (this.window) this.commit(null);
      return;
    }
    const t0 = parseIsoUtc(a);
    const t1 = parseIsoUtc(b);
    if (t0 === null || t1 === null) {
      this.showTypedError(`Not an ISO 8601 time: ${t0 === null ? a || '(empty start)' : b || '(empty end)'} (e.g. 2018-01-01T10:15:00Z)`);
      return;
    }
    if (!(t1 > t0)) {
      this.showTypedError('The window ends before it starts.');
      return;
    }
    const d = this.domain;
    if (d && (t1 <= d.start || t0 >= d.end)) {
      this.showTypedError(`Outside the data (${formatIsoUtc(d.start)} → ${formatIsoUtc(d.end)}).`);
      return;
    }
    this.showTypedError(null);
    this.commit({ start: Math.floor(t0), end: Math.ceil(t1) });
  }

  private showTypedError(msg: string | null) {
    this.typedError.hidden = msg === null;
    this.typedError.textContent = msg ?? '';
    this.t0Input.toggleAttribute('aria-invalid', msg !== null);
    this.t1Input.toggleAttribute('aria-invalid', msg !== null);
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
    this.tooltip.textContent = `${formatUtcSeconds(t)} · bin ${formatUtcSeconds(b0)}–${formatUtcSeconds(b0 + hist.bin_seconds).slice(11)}: ${formatInt(hist.counts[i])} points`;
    this.tooltip.hidden = false;
    const tw = this.tooltip.offsetWidth;
    this.tooltip.style.left = `${Math.min(Math.max(0, x - tw / 2), this.width - tw)}px`;
  }

  private updateReadout() {
    const w = this.window;
    const a = w ? formatUtcSeconds(w.start) : '';
    const b = w ? formatUtcSeconds(w.end) : '';
    this.readout.textContent = w ? `${a.slice(11)} → ${a.slice(0, 10) === b.slice(0, 10) ? b.slice(11) : b} · ${formatDuration(w.end - w.start)}` : 'All times';
    this.plot.dataset.t0 = w ? String(w.start) : '';
    this.plot.dataset.t1 = w ? String(w.end) : '';
    const v = this.getView();
    this.plot.dataset.viewT0 = v ? String(v.start) : '';
    this.plot.dataset.viewT1 = v ? String(v.end) : '';
    // The typed fields follow the window when it changes (not on every redraw: a half-typed pair stays).
    const key = w ? `${w.start},${w.end}` : '';
    if (key !== this.typedFor) {
      this.typedFor = key;
      // A window set another way (drag, keys, URL) replaces whatever was typed, and its error.
      if (document.activeElement !== this.t0Input && document.activeElement !== this.t1Input) this.showTypedError(null);
      for (const [el, t] of [
        [this.t0Input, w?.start],
        [this.t1Input, w?.end],
      ] as const) {
        if (document.activeElement !== el) el.value = t === undefined ? '' : formatIsoUtc(t);
      }
    }
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
    const d = this.view;
    if (!hist || !d || W === 0 || H === 0) {
      this.cursorEl = null;
      mount(this.svgEl, svg('text', { x: W / 2, y: H / 2, class: 'brush-empty', 'text-anchor': 'middle', 'dominant-baseline': 'middle' }, this.state === 'loading' ? 'Loading…' : this.message));
      return;
    }
    const ph = this.plotH();
    const base = TOP_PAD + ph;
    // Bars of the bins inside the view (the histogram may be of the whole data set or of the view).
    const first = Math.max(0, Math.floor((d.start - hist.t0) / hist.bin_seconds));
    const last = Math.min(hist.counts.length - 1, Math.floor((d.end - hist.t0) / hist.bin_seconds));
    let max = 0;
    for (let i = first; i <= last; i++) max = Math.max(max, hist.counts[i]!);
    const bars = svg('g', { class: 'bars' });
    const bw = (hist.bin_seconds / (d.end - d.start)) * W;
    const gap = bw > 4 ? 1 : 0;
    for (let i = first; i <= last; i++) {
      const c = hist.counts[i]!;
      if (c <= 0) continue;
      const b0 = hist.t0 + i * hist.bin_seconds;
      const x = timeToX(b0, d, W);
      const bh = Math.max(1, (c / Math.max(1, max)) * ph);
      const w = this.window;
      const inWin = !w || (b0 < w.end && b0 + hist.bin_seconds > w.start);
      bars.append(svg('rect', { x: x + gap / 2, y: base - bh, width: Math.max(0.5, bw - gap), height: bh, class: inWin ? 'bar in' : 'bar' }));
    }

    // Axis: d3's UTC time scale picks round ticks for any zoom, from days down to seconds.
    const axis = svg('g', { class: 'axis time-axis', transform: `translate(0,${base})` });
    const scale = scaleUtc()
      .domain([new Date(d.start * 1000), new Date(d.end * 1000)])
      .range([0, W]);
    select(axis).call(
      axisBottom(scale)
        .ticks(Math.max(2, Math.floor(W / 110)))
        .tickFormat((v) => utcTick(v as Date))
        .tickSizeOuter(0)
        .tickSize(4),
    );
    const yLabel =
      max > 0
        ? svg('text', { x: 4, y: TOP_PAD + 9, class: 'tick-label ymax' }, `${formatCompact(max)} pts/bin (${formatDuration(hist.bin_seconds)})`)
        : svg('text', { x: W / 2, y: TOP_PAD + ph / 2, class: 'brush-empty', 'text-anchor': 'middle', 'dominant-baseline': 'middle' }, 'No traffic matches the other filters.');

    const children: SVGElement[] = [bars, axis, yLabel];
    const wp = this.winPx(this.window);
    if (wp) {
      const x0 = Math.max(-4, Math.min(W + 4, wp.x0));
      const x1 = Math.max(-4, Math.min(W + 4, wp.x1));
      children.push(
        svg('rect', { x: 0, y: TOP_PAD, width: Math.max(0, x0), height: ph, class: 'shade' }),
        svg('rect', { x: x1, y: TOP_PAD, width: Math.max(0, W - x1), height: ph, class: 'shade' }),
        svg('rect', { x: x0, y: TOP_PAD, width: Math.max(1, x1 - x0), height: ph, class: 'selection' }),
        svg('rect', { x: x0 - 2, y: TOP_PAD + ph / 2 - 10, width: 4, height: 20, rx: 1.5, class: 'handle' }),
        svg('rect', { x: x1 - 2, y: TOP_PAD + ph / 2 - 10, width: 4, height: 20, rx: 1.5, class: 'handle' }),
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

const fmtDay = utcFormat('%b %d');
const fmtMinute = utcFormat('%H:%M');
const fmtSecond = utcFormat('%H:%M:%S');

/** A UTC tick label in 24-hour time: the date at midnight, seconds only when the tick has them. */
function utcTick(d: Date): string {
  if (d.getUTCSeconds() !== 0) return fmtSecond(d);
  if (d.getUTCHours() === 0 && d.getUTCMinutes() === 0) return fmtDay(d);
  return fmtMinute(d);
}
