// The model-state view: one column per frame coloured by the tracker state (blue TRACK, red LOST, grey
// SEARCH; dark = not computed yet), with the current-frame cursor. Click or drag to seek.

import { h, mount, sectionHead } from '../lib/dom';
import { AxisSurface } from './axisSurface';
import { frameLeft, tickStep, xOfFrame } from './frameAxis';
import { CODE_STATE, type FrameStore } from './frameStore';
import { STATE_COLORS, UNKNOWN_COLOR } from './palette';

export class StateTimeline {
  readonly root: HTMLElement;
  readonly surface: AxisSurface;
  private store: FrameStore | null = null;
  private readonly counts: HTMLElement;

  constructor(onSeek: (frame: number) => void) {
    this.surface = new AxisSurface({
      label: 'Tracker state per frame; click to select a frame',
      testid: 'state-timeline',
      onSeek,
      draw: (ctx, w, hgt) => this.draw(ctx, w, hgt),
      describe: (f) => {
        const st = this.store ? CODE_STATE[this.store.states[f] ?? 0] : null;
        return `frame ${f}: ${st ?? 'not computed'}`;
      },
    });
    this.counts = h('span', { class: 'timeline-counts muted small', 'data-testid': 'state-counts' });
    const key = (label: string, color: string) => h('span', { class: 'legend-item' }, h('span', { class: 'legend-block', style: `background:${color}` }), label);
    this.root = h(
      'section',
      { class: 'tracker-panel state-timeline-panel', 'aria-label': 'State timeline' },
      sectionHead(
        'Model state',
        h('span', { class: 'legend' }, key('track', STATE_COLORS.TRACK), key('lost', STATE_COLORS.LOST), key('search', STATE_COLORS.SEARCH), this.counts),
      ),
      this.surface.root,
      this.axis,
    );
    new ResizeObserver(() => this.renderAxis()).observe(this.axis);
  }

  private readonly axis = h('div', { class: 'frame-ticks', 'aria-hidden': 'true' });

  /** Frame numbers under the timeline (1-2-5 steps, about one per 80 px). */
  private renderAxis() {
    const n = this.store?.frames ?? 0;
    const w = this.axis.clientWidth;
    if (n === 0 || w === 0) {
      mount(this.axis);
      return;
    }
    const step = tickStep(n, Math.max(2, Math.floor(w / 80)));
    const ticks: HTMLElement[] = [];
    for (let f = 0; f < n; f += step) ticks.push(h('span', { class: 'frame-tick', style: `left:${xOfFrame(f, w, n).toFixed(1)}px` }, String(f)));
    mount(this.axis, ...ticks);
  }

  setStore(store: FrameStore): void {
    this.store = store;
    this.surface.setFrames(store.frames);
    this.renderAxis();
    this.update();
  }

  /** The store grew. */
  update(): void {
    if (!this.store) return;
    const c = this.store.stateCounts();
    const d = this.surface.root.dataset;
    d.track = String(c.TRACK);
    d.lost = String(c.LOST);
    d.search = String(c.SEARCH);
    d.known = String(this.store.knownCount);
    this.counts.textContent = `${c.TRACK} track · ${c.LOST} lost · ${c.SEARCH} search${this.store.complete ? '' : ` · ${this.store.knownCount}/${this.store.frames} known`}`;
    this.surface.invalidate();
  }

  private draw(ctx: CanvasRenderingContext2D, w: number, hgt: number) {
    const s = this.store;
    if (!s || s.frames === 0) return;
    const n = s.frames;
    // Runs of equal state as one rectangle each.
    let start = 0;
    for (let i = 1; i <= n; i++) {
      if (i < n && s.states[i] === s.states[start]) continue;
      const st = CODE_STATE[s.states[start] ?? 0];
      ctx.fillStyle = st ? STATE_COLORS[st] : UNKNOWN_COLOR;
      const x0 = Math.floor(frameLeft(start, w, n));
      const x1 = Math.ceil(frameLeft(i, w, n));
      ctx.fillRect(x0, 0, Math.max(1, x1 - x0), hgt);
      start = i;
    }
  }
}
