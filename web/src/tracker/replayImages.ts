// The replay view: depth and amplitude side by side, each scaled ×SCALE with crisp pixels, with the
// tracker's overlays. Frames can arrive faster than they can be decoded: only the newest one is decoded
// and drawn (one decode in flight at a time).

import type { FrameRecord, FrameTruth } from '../api/trackerLog';
import { h } from '../lib/dom';
import { drawOverlays, type OverlayCounts, type OverlayOptions } from './overlays';
import { CANDIDATE_REJECTED, CANDIDATE_VERIFIED, TEAT_COLORS } from './palette';
import type { ShownFrame } from './storedRun';

export const SCALE = 3;

interface Pane {
  canvas: HTMLCanvasElement;
  image: ImageBitmap | null;
}

export class ReplayImages {
  readonly root: HTMLElement;
  private readonly panes: Pane[];
  private width = 0;
  private height = 0;
  private pending: ShownFrame | null = null;
  private decoding = false;
  private record: FrameRecord | null = null;
  private truth: FrameTruth | null = null;
  private shownIndex = -1;
  /** Bumped by reset(): a decode still in flight for the previous replay is dropped. */
  private generation = 0;
  private readonly opts: OverlayOptions = { candidates: true, estimates: true, truth: true };

  constructor() {
    const pane = (label: string, id: string): [HTMLElement, Pane] => {
      const canvas = h('canvas', { class: 'replay-canvas', 'data-testid': `replay-${id}`, 'aria-label': `${label} image with overlays` });
      return [h('figure', { class: 'replay-pane' }, h('figcaption', {}, label), canvas), { canvas, image: null }];
    };
    const [depthFig, depth] = pane('Depth', 'depth');
    const [ampFig, amp] = pane('Amplitude', 'amplitude');
    this.panes = [depth, amp];
    const toggle = (key: keyof OverlayOptions, label: string, swatch: HTMLElement) => {
      const input = h('input', { type: 'checkbox', checked: true, 'data-testid': `overlay-${key}` });
      input.addEventListener('change', () => {
        this.opts[key] = input.checked;
        this.redraw();
      });
      return h('label', { class: 'overlay-toggle' }, input, swatch, label);
    };
    const sw = (style: string) => h('span', { class: 'legend-swatch', style });
    this.root = h(
      'div',
      { class: 'replay-images', 'data-testid': 'replay-images', 'data-frame': '-1' },
      h('div', { class: 'replay-panes' }, depthFig, ampFig),
      h(
        'div',
        { class: 'overlay-legend' },
        toggle('candidates', 'candidates (verified / rejected)', h('span', {}, sw(`border-color:${CANDIDATE_VERIFIED}`), sw(`border-color:${CANDIDATE_REJECTED}`))),
        toggle('estimates', 'teat estimates (dashed = predicted)', h('span', {}, ...TEAT_COLORS.map((c) => sw(`border-color:${c}`)))),
        toggle('truth', 'ground truth (× tip, box)', h('span', { class: 'legend-cross' }, '×')),
      ),
    );
  }

  setSize(width: number, height: number): void {
    if (width === this.width && height === this.height) return;
    this.width = width;
    this.height = height;
    for (const p of this.panes) {
      p.canvas.width = width * SCALE;
      p.canvas.height = height * SCALE;
      p.image?.close();
      p.image = null;
    }
    this.redraw();
  }

  /** Forgets the pictures of the previous replay. */
  reset(width: number, height: number): void {
    this.generation++;
    this.pending = null;
    this.record = null;
    this.truth = null;
    this.shownIndex = -1;
    for (const p of this.panes) {
      p.image?.close();
      p.image = null;
    }
    this.width = -1;
    this.setSize(width, height);
  }

  /** Queues a frame (from the socket, or a stored run's pictures); the newest queued frame wins. */
  show(msg: ShownFrame): void {
    this.pending = msg;
    if (!this.decoding) void this.pump();
  }

  private async pump() {
    this.decoding = true;
    try {
      while (this.pending) {
        const msg = this.pending;
        this.pending = null;
        const gen = this.generation;
        const images = await Promise.all([msg.depthPng, msg.amplitudePng].map((png) => (png ? decodePng(png) : Promise.resolve(null))));
        if (gen !== this.generation) {
          for (const img of images) img?.close();
          continue;
        }
        images.forEach((img, i) => {
          const p = this.panes[i]!;
          p.image?.close();
          p.image = img;
        });
        if (this.width === 0 && images[0]) this.setSize(images[0].width, images[0].height);
        this.record = msg.frame;
        this.truth = msg.truth;
        this.shownIndex = msg.index;
        this.redraw();
        await nextFrame();
      }
    } finally {
      this.decoding = false;
    }
  }

  private redraw() {
    let counts: OverlayCounts | null = null;
    for (const p of this.panes) {
      const ctx = p.canvas.getContext('2d');
      if (!ctx) continue;
      ctx.imageSmoothingEnabled = false;
      ctx.fillStyle = '#05070a';
      ctx.fillRect(0, 0, p.canvas.width, p.canvas.height);
      if (p.image) ctx.drawImage(p.image, 0, 0, p.canvas.width, p.canvas.height);
      counts = drawOverlays(ctx, SCALE, this.record, this.truth, this.opts);
    }
    const d = this.root.dataset;
    d.frame = String(this.shownIndex);
    d.hasImage = String(this.panes.some((p) => p.image !== null));
    if (counts) {
      d.candidates = String(counts.candidates);
      d.estimates = String(counts.estimates);
      d.truthTips = String(counts.truthTips);
      d.truthBoxes = String(counts.truthBoxes);
    }
  }
}

async function decodePng(png: Uint8Array): Promise<ImageBitmap | null> {
  try {
    return await createImageBitmap(new Blob([png as BlobPart], { type: 'image/png' }));
  } catch {
    return null;
  }
}

/** The next animation frame, or 50 ms when the page is not painting (a background tab). */
function nextFrame(): Promise<void> {
  return new Promise((r) => {
    const t = window.setTimeout(r, 50);
    requestAnimationFrame(() => {
      window.clearTimeout(t);
      r();
    });
  });
}
