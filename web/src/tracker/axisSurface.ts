// The interactive strip shared by the frame-axis views: a canvas that fills its host, a current-frame
// cursor, a hover readout, and click/drag → seek (the frame under the pointer, frameAxis.frameAt).

import { cssContext, fitCanvas, h } from '../lib/dom';
import { frameAt, xOfFrame } from './frameAxis';

export interface AxisSurfaceOptions {
  label: string;
  testid: string;
  onSeek(frame: number): void;
  /** Redraw the canvas (CSS px size, device pixel ratio applied to the context already). */
  draw(ctx: CanvasRenderingContext2D, width: number, height: number): void;
  /** Hover text for a frame. */
  describe?(frame: number): string;
}

export class AxisSurface {
  readonly root: HTMLElement;
  readonly canvas: HTMLCanvasElement;
  private readonly cursor: HTMLElement;
  private readonly hover: HTMLElement;
  private frames = 0;
  private frame = 0;
  private width = 0;
  private height = 0;
  private dirty = false;
  private dragging = false;

  constructor(private readonly opts: AxisSurfaceOptions) {
    this.canvas = h('canvas', { class: 'axis-canvas' });
    this.cursor = h('div', { class: 'axis-cursor', hidden: true });
    this.hover = h('div', { class: 'axis-hover', hidden: true });
    this.root = h(
      'div',
      { class: 'axis-surface', role: 'slider', tabindex: -1, 'aria-label': opts.label, 'data-testid': opts.testid, 'data-frames': '0', 'data-cursor': '0' },
      this.canvas,
      this.cursor,
      this.hover,
    );
    new ResizeObserver(() => this.resize()).observe(this.root);
    this.root.addEventListener('pointerdown', (e) => {
      if (e.button !== 0 || this.frames === 0) return;
      this.dragging = true;
      this.root.setPointerCapture(e.pointerId);
      this.seekAt(e);
    });
    this.root.addEventListener('pointermove', (e) => {
      if (this.dragging) this.seekAt(e);
      this.showHover(e);
    });
    const end = () => (this.dragging = false);
    this.root.addEventListener('pointerup', end);
    this.root.addEventListener('pointercancel', end);
    this.root.addEventListener('pointerleave', () => (this.hover.hidden = true));
  }

  setFrames(n: number): void {
    this.frames = n;
    this.root.dataset.frames = String(n);
    this.placeCursor();
    this.invalidate();
  }

  setCursor(frame: number): void {
    this.frame = frame;
    this.root.dataset.cursor = String(frame);
    this.root.setAttribute('aria-valuenow', String(frame));
    this.placeCursor();
  }

  /** Schedules a redraw (coalesced to one per animation frame). */
  invalidate(): void {
    if (this.dirty) return;
    this.dirty = true;
    const run = () => {
      if (!this.dirty) return;
      this.dirty = false;
      this.redraw();
    };
    requestAnimationFrame(run);
    window.setTimeout(run, 100); // background tabs do not paint
  }

  /** Client x (viewport) of a frame's centre: for tests and keyboard users. */
  clientXOf(frame: number): number {
    return this.root.getBoundingClientRect().left + xOfFrame(frame, this.width, this.frames);
  }

  private frameOf(e: PointerEvent): number {
    const r = this.root.getBoundingClientRect();
    return frameAt(e.clientX - r.left, r.width, this.frames);
  }

  private seekAt(e: PointerEvent) {
    const f = this.frameOf(e);
    if (f !== this.frame || !this.dragging) this.opts.onSeek(f);
    this.setCursor(f);
  }

  private showHover(e: PointerEvent) {
    if (!this.opts.describe || this.frames === 0) return;
    const f = this.frameOf(e);
    const r = this.root.getBoundingClientRect();
    this.hover.hidden = false;
    this.hover.textContent = this.opts.describe(f);
    const x = e.clientX - r.left;
    this.hover.style.left = `${Math.min(Math.max(0, x + 8), Math.max(0, r.width - 160))}px`;
  }

  private placeCursor() {
    this.cursor.hidden = this.frames === 0 || this.width === 0;
    const w = Math.max(1, this.width / Math.max(1, this.frames));
    this.cursor.style.left = `${(this.frame * this.width) / Math.max(1, this.frames)}px`;
    this.cursor.style.width = `${Math.max(2, w)}px`;
  }

  private resize() {
    ({ width: this.width, height: this.height } = fitCanvas(this.canvas, this.root));
    this.placeCursor();
    this.dirty = false;
    this.redraw();
  }

  private redraw() {
    if (this.width === 0 || this.height === 0) return;
    const ctx = cssContext(this.canvas, this.width, this.height);
    if (!ctx) return;
    this.opts.draw(ctx, this.width, this.height);
  }
}
