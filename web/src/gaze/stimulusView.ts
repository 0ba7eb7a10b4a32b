// The stimulus view: the stimulus image, the stimulus-space density tiles over it (a canvas each), and an
// SVG overlay with saccades, bundled saccades, scanpaths (fixation circles sized by duration, numbered,
// joined in order) and the areas of interest. d3-zoom pans and zooms all of them with one transform from
// stimulus pixels to CSS pixels; the tiles are asked for at the zoom that matches it (geometry.ts). AOIs
// are drawn here: a drag spans a rectangle, clicks place a polygon's vertices (closed on its first vertex
// or by a double-click).

import { select, type Selection } from 'd3-selection';
import { zoom, zoomIdentity, type D3ZoomEvent, type ZoomBehavior, type ZoomTransform } from 'd3-zoom';
import { pointer } from 'd3-selection';
import { scaleLinear } from 'd3-scale';
import type { Aoi, Fixation, GazeEvent, Scanpath } from '../api/gazeTypes';
import { h, svg } from '../lib/dom';
import { aoiPath, closesPolygon, scanpathSpanMs, dragRect, fitTransform, fixationRadius, maxFixationMs, paintedPixels, tileSide, tileZoom, visibleTiles } from './geometry';

export type DrawMode = 'none' | 'rect' | 'polygon';

/** Colours of the scanpaths' lines, one per recording (cycled). */
export const PATH_COLORS = ['#4cc9f0', '#f72585', '#b5e48c', '#ffd166', '#c77dff', '#ff8c42', '#80ffdb', '#ef476f', '#a0c4ff', '#caffbf'];
/** The fixation fill ramp: start time from the recording's first fixation, early → late (viridis ends). */
export const FIXATION_RAMP = ['#440154', '#3e4989', '#26828e', '#35b779', '#fde725'];

export interface StimulusViewEvents {
  /** A rectangle or polygon was drawn (stimulus pixels). */
  onAoiDrawn(shape: { rect: [number, number, number, number] } | { polygon: [number, number][] }): void;
  /** The tile zoom changed (the density legend follows it). */
  onTileZoom(z: number): void;
}

/** Tile images kept at most (older ones are dropped first). */
const TILE_CACHE = 256;

export class StimulusView {
  readonly el: HTMLElement;
  private readonly imageCanvas: HTMLCanvasElement;
  private readonly densityCanvas: HTMLCanvasElement;
  private readonly overlay: SVGSVGElement;
  private readonly world: SVGGElement;
  private readonly layers: Record<'bundles' | 'saccades' | 'scanpaths' | 'aois' | 'draft', SVGGElement>;
  private readonly zoomer: ZoomBehavior<SVGSVGElement, unknown>;
  private readonly sel: Selection<SVGSVGElement, unknown, null, undefined>;
  private t: ZoomTransform = zoomIdentity;
  private width = 0;
  private height = 0;
  private image: HTMLImageElement | null = null;
  private tileUrl: ((z: number, x: number, y: number) => string) | null = null;
  private readonly tiles = new Map<string, HTMLImageElement>();
  private densityOpacity = 0.75;
  private frame = 0;
  private countTimer: number | undefined;
  private mode: DrawMode = 'none';
  private dragStart: [number, number] | null = null;
  private vertices: [number, number][] = [];
  private z = -1;
  private fitted = false;
  /** The user panned or zoomed: a resize keeps their view instead of fitting the stimulus again. */
  private userMoved = false;

  constructor(private readonly events: StimulusViewEvents) {
    this.imageCanvas = h('canvas', { class: 'gaze-layer', 'data-testid': 'gaze-image' });
    this.densityCanvas = h('canvas', { class: 'gaze-layer', 'data-testid': 'gaze-density', 'data-painted': '0', 'data-tiles': '0' });
    this.overlay = svg('svg', { class: 'gaze-layer gaze-overlay', 'data-testid': 'gaze-overlay' });
    this.world = svg('g', { class: 'gaze-world' });
    this.layers = {
      bundles: svg('g', { class: 'gaze-bundles', 'data-testid': 'gaze-bundles' }),
      saccades: svg('g', { class: 'gaze-saccades', 'data-testid': 'gaze-saccades' }),
      scanpaths: svg('g', { class: 'gaze-scanpaths', 'data-testid': 'gaze-scanpaths' }),
      aois: svg('g', { class: 'gaze-aois', 'data-testid': 'gaze-aois' }),
      draft: svg('g', { class: 'gaze-draft' }),
    };
    this.world.append(this.layers.bundles, this.layers.saccades, this.layers.scanpaths, this.layers.aois, this.layers.draft);
    this.overlay.append(this.world);
    this.el = h('div', { class: 'gaze-stage', 'data-testid': 'gaze-stage', 'data-mode': 'none' }, this.imageCanvas, this.densityCanvas, this.overlay);

    this.sel = select(this.overlay);
    this.zoomer = zoom<SVGSVGElement, unknown>()
      .scaleExtent([0.02, 64])
      // While drawing, the pointer draws: only the wheel zooms.
      .filter((ev: Event) => (this.mode === 'none' ? !(ev as MouseEvent).button && !(ev as MouseEvent).ctrlKey : ev.type === 'wheel'))
      .on('zoom', (ev: D3ZoomEvent<SVGSVGElement, unknown>) => {
        this.t = ev.transform;
        if (ev.sourceEvent) this.userMoved = true;
        this.el.dataset.k = String(this.t.k);
        this.world.setAttribute('transform', this.t.toString());
        this.schedule();
      });
    this.sel.call(this.zoomer).on('dblclick.zoom', null);
    this.overlay.addEventListener('pointerdown', (e) => this.pointerDown(e));
    this.overlay.addEventListener('pointermove', (e) => this.pointerMove(e));
    this.overlay.addEventListener('pointerup', (e) => this.pointerUp(e));
    this.overlay.addEventListener('dblclick', (e) => this.finishPolygon(e));
    new ResizeObserver(() => {
      if ((!this.fitted || !this.userMoved) && this.width > 0) this.fit();
      this.schedule();
    }).observe(this.el);
  }

  /** The stimulus: its size in pixels and its image (null: a blank stimulus-sized frame). */
  setStimulus(width: number, height: number, image: HTMLImageElement | null): void {
    const changed = width !== this.width || height !== this.height;
    this.width = width;
    this.height = height;
    this.image = image;
    this.el.dataset.stimulusWidth = String(width);
    this.el.dataset.stimulusHeight = String(height);
    this.el.dataset.hasImage = String(!!image);
    if (changed || !this.fitted) this.fit();
    this.schedule();
  }

  /** Fits the whole stimulus into the view (and forgets the user's pan and zoom). */
  fit(): void {
    this.userMoved = false;
    const r = this.el.getBoundingClientRect();
    if (!(this.width > 0) || r.width < 10 || r.height < 10) return;
    const f = fitTransform(this.width, this.height, r.width, r.height);
    this.fitted = true;
    this.sel.call(this.zoomer.transform, zoomIdentity.translate(f.x, f.y).scale(f.k));
  }

  /** The density tiles' URL maker (null: no density layer) and the layer's opacity. */
  setDensity(tileUrl: ((z: number, x: number, y: number) => string) | null, opacity = this.densityOpacity): void {
    this.tileUrl = tileUrl;
    this.densityOpacity = opacity;
    this.densityCanvas.dataset.painted = '0';
    this.densityCanvas.dataset.state = tileUrl ? 'loading' : 'off';
    this.schedule();
  }

  /**
   * Draws the scanpaths: per recording a line through its fixations, then numbered circles (area by
   * duration) filled by their start after the path's first fixation on one ramp for all (FIXATION_RAMP
   * over 0 … the longest such span). Returns that span (ms) for the legend.
   */
  setScanpaths(paths: readonly Scanpath[]): number {
    const g = this.layers.scanpaths;
    g.replaceChildren();
    const radius = fixationRadius(maxFixationMs(paths));
    const span = scanpathSpanMs(paths);
    const fill = scaleLinear<string>()
      .domain(FIXATION_RAMP.map((_, k) => ((span || 1) * k) / (FIXATION_RAMP.length - 1)))
      .range(FIXATION_RAMP)
      .clamp(true);
    let drawn = 0;
    paths.forEach((path, i) => {
      // A fixation without a valid position (null centroid) has no place on the stimulus.
      const p = { ...path, fixations: path.fixations.filter((f): f is Fixation & { x: number; y: number } => f.x !== null && f.y !== null) };
      const color = PATH_COLORS[i % PATH_COLORS.length]!;
      const pg = svg('g', { class: 'scanpath', 'data-recording': p.recording, 'data-participant': p.participant, 'data-fixations': p.fixations.length });
      if (p.fixations.length > 1) {
        pg.append(svg('path', { class: 'scanpath-line', d: `M${p.fixations.map((f) => `${f.x},${f.y}`).join('L')}`, stroke: color }));
      }
      const t0 = p.fixations.length ? p.fixations[0]!.t_start_ms : 0;
      p.fixations.forEach((f, k) => {
        const r = radius(f.duration_ms);
        pg.append(
          svg(
            'circle',
            { class: 'fixation', cx: f.x, cy: f.y, r, fill: fill(f.t_start_ms - t0), stroke: color, 'data-duration': f.duration_ms },
            svg('title', {}, `${p.participant} #${k + 1}: ${Math.round(f.duration_ms)} ms, ${Math.round(f.t_start_ms - t0)} ms after the first`),
          ),
          svg('text', { class: 'fixation-number', x: f.x, y: f.y, 'font-size': Math.max(7, Math.min(14, r)) }, String(k + 1)),
        );
        drawn++;
      });
      g.append(pg);
    });
    g.dataset.fixations = String(drawn);
    g.dataset.paths = String(paths.length);
    return span;
  }

  /** Saccades as arrows from their start to their end (events with both ends). */
  setSaccades(events: readonly GazeEvent[]): void {
    const g = this.layers.saccades;
    g.replaceChildren();
    let n = 0;
    for (const e of events) {
      if (e.type !== 'saccade' || e.x === null || e.y === null || e.x_end === null || e.y_end === null) continue;
      g.append(svg('line', { class: 'saccade', x1: e.x, y1: e.y, x2: e.x_end, y2: e.y_end, 'marker-end': 'url(#gaze-arrow)' }));
      n++;
    }
    g.dataset.saccades = String(n);
    this.ensureArrow();
  }

  /** Bundled saccades: polylines in stimulus pixels with a colour each. */
  setBundles(lines: readonly { points: Float64Array | number[]; color: string }[]): void {
    const g = this.layers.bundles;
    g.replaceChildren();
    for (const l of lines) {
      const p = l.points;
      if (p.length < 4) continue;
      let d = `M${p[0]},${p[1]}`;
      for (let i = 2; i < p.length; i += 2) d += `L${p[i]},${p[i + 1]}`;
      g.append(svg('path', { class: 'bundle-line', d, stroke: l.color }));
    }
    g.dataset.lines = String(g.childElementCount);
  }

  setAois(aois: readonly Aoi[], selected: string | null = null): void {
    const g = this.layers.aois;
    g.replaceChildren();
    for (const a of aois) {
      const c = this.aoiCentre(a);
      g.append(
        svg('path', { class: `aoi${a.name === selected ? ' selected' : ''}`, d: aoiPath(a), 'data-name': a.name }),
        svg('text', { class: 'aoi-label', x: c[0], y: c[1] }, a.name),
      );
    }
    g.dataset.count = String(aois.length);
  }

  setMode(mode: DrawMode): void {
    this.mode = mode;
    this.el.dataset.mode = mode;
    this.dragStart = null;
    this.vertices = [];
    this.layers.draft.replaceChildren();
  }

  /** Stimulus pixels → CSS pixels of the stage (for tests and tooltips). */
  toScreen(p: [number, number]): [number, number] {
    return this.t.apply(p);
  }

  private aoiCentre(a: Aoi): [number, number] {
    if ('rect' in a) return [(a.rect[0] + a.rect[2]) / 2, (a.rect[1] + a.rect[3]) / 2];
    const n = a.polygon.length;
    return [a.polygon.reduce((s, p) => s + p[0], 0) / n, a.polygon.reduce((s, p) => s + p[1], 0) / n];
  }

  private ensureArrow() {
    if (this.overlay.querySelector('#gaze-arrow')) return;
    const defs = svg(
      'defs',
      {},
      svg(
        'marker',
        { id: 'gaze-arrow', viewBox: '0 0 10 10', refX: 9, refY: 5, markerWidth: 6, markerHeight: 6, orient: 'auto-start-reverse' },
        svg('path', { d: 'M0,0L10,5L0,10Z', class: 'saccade-head' }),
      ),
    );
    this.overlay.prepend(defs);
  }

  private stimulusPoint(e: PointerEvent | MouseEvent): [number, number] {
    return this.t.invert(pointer(e, this.overlay));
  }

  private pointerDown(e: PointerEvent) {
    if (this.mode === 'none' || e.button !== 0) return;
    e.preventDefault();
    const p = this.stimulusPoint(e);
    if (this.mode === 'rect') {
      this.dragStart = p;
      this.overlay.setPointerCapture(e.pointerId);
      return;
    }
    // polygon: a click near the first vertex closes it
    if (closesPolygon(this.vertices, p, 8 / this.t.k)) {
      this.closePolygon();
      return;
    }
    this.vertices.push(p);
    this.drawDraft(p);
  }

  private pointerMove(e: PointerEvent) {
    if (this.mode === 'rect' && this.dragStart) this.drawDraft(this.stimulusPoint(e));
    else if (this.mode === 'polygon' && this.vertices.length) this.drawDraft(this.stimulusPoint(e));
  }

  private pointerUp(e: PointerEvent) {
    if (this.mode !== 'rect' || !this.dragStart) return;
    const r = dragRect(this.dragStart, this.stimulusPoint(e), this.width, this.height);
    this.dragStart = null;
    this.layers.draft.replaceChildren();
    if (r) this.events.onAoiDrawn({ rect: r });
  }

  private finishPolygon(e: MouseEvent) {
    if (this.mode !== 'polygon') return;
    e.preventDefault();
    // The double-click's two clicks added the same vertex twice: keep one.
    const v = this.vertices;
    if (v.length >= 2 && v[v.length - 1]![0] === v[v.length - 2]![0] && v[v.length - 1]![1] === v[v.length - 2]![1]) v.pop();
    if (v.length >= 3) this.closePolygon();
  }

  private closePolygon() {
    const clip = (p: [number, number]): [number, number] => [
      Math.round(Math.max(0, Math.min(this.width, p[0])) * 100) / 100,
      Math.round(Math.max(0, Math.min(this.height, p[1])) * 100) / 100,
    ];
    const polygon = this.vertices.map(clip);
    this.vertices = [];
    this.layers.draft.replaceChildren();
    this.events.onAoiDrawn({ polygon });
  }

  private drawDraft(p: [number, number]) {
    const g = this.layers.draft;
    g.replaceChildren();
    if (this.mode === 'rect' && this.dragStart) {
      const [a, b] = [this.dragStart, p];
      g.append(svg('rect', { class: 'aoi draft', x: Math.min(a[0], b[0]), y: Math.min(a[1], b[1]), width: Math.abs(a[0] - b[0]), height: Math.abs(a[1] - b[1]) }));
    } else if (this.mode === 'polygon' && this.vertices.length) {
      const pts = [...this.vertices, p];
      g.append(svg('path', { class: 'aoi draft', d: `M${pts.map(([x, y]) => `${x},${y}`).join('L')}` }));
    }
  }

  private schedule() {
    if (this.frame) return;
    this.frame = requestAnimationFrame(() => {
      this.frame = 0;
      this.draw();
    });
  }

  private sizeCanvas(c: HTMLCanvasElement, w: number, hgt: number, dpr: number): CanvasRenderingContext2D | null {
    const W = Math.max(1, Math.round(w * dpr));
    const H = Math.max(1, Math.round(hgt * dpr));
    if (c.width !== W || c.height !== H) {
      c.width = W;
      c.height = H;
    }
    const ctx = c.getContext('2d', { willReadFrequently: c === this.densityCanvas });
    if (!ctx) return null;
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.clearRect(0, 0, W, H);
    ctx.setTransform(dpr * this.t.k, 0, 0, dpr * this.t.k, dpr * this.t.x, dpr * this.t.y);
    return ctx;
  }

  private draw() {
    const r = this.el.getBoundingClientRect();
    const dpr = window.devicePixelRatio || 1;
    const img = this.sizeCanvas(this.imageCanvas, r.width, r.height, dpr);
    const den = this.sizeCanvas(this.densityCanvas, r.width, r.height, dpr);
    if (!img || !den || !(this.width > 0)) return;
    if (this.image) img.drawImage(this.image, 0, 0, this.width, this.height);
    else {
      img.fillStyle = '#1a1f27';
      img.fillRect(0, 0, this.width, this.height);
    }
    img.strokeStyle = '#5a6472';
    img.lineWidth = 1 / this.t.k;
    img.strokeRect(0, 0, this.width, this.height);

    const side = tileSide(this.width, this.height);
    const z = tileZoom(this.t.k * dpr, side);
    if (z !== this.z) {
      this.z = z;
      this.densityCanvas.dataset.z = String(z);
      this.events.onTileZoom(z);
    }
    if (!this.tileUrl) return;
    const [vx0, vy0] = this.t.invert([0, 0]);
    const [vx1, vy1] = this.t.invert([r.width, r.height]);
    const want = visibleTiles(z, this.width, this.height, { x0: vx0, y0: vy0, x1: vx1, y1: vy1 });
    den.globalAlpha = this.densityOpacity;
    den.imageSmoothingEnabled = false;
    let loaded = 0;
    let pending = 0;
    for (const t of want) {
      const url = this.tileUrl(t.z, t.x, t.y);
      const im = this.tile(url);
      if (im.complete && im.naturalWidth > 0) {
        den.drawImage(im, t.x0, t.y0, t.size, t.size);
        loaded++;
      } else if (!im.complete) pending++;
    }
    this.densityCanvas.dataset.tiles = String(loaded);
    this.densityCanvas.dataset.wanted = String(want.length);
    if (pending === 0) {
      // Every wanted tile is in (or failed): count the painted pixels once the view rests.
      window.clearTimeout(this.countTimer);
      this.countTimer = window.setTimeout(() => this.countPainted(), 120);
    } else this.densityCanvas.dataset.state = 'loading';
  }

  private countPainted() {
    const c = this.densityCanvas;
    const ctx = c.getContext('2d', { willReadFrequently: true });
    if (!ctx || !this.tileUrl) return;
    c.dataset.painted = String(paintedPixels(ctx.getImageData(0, 0, c.width, c.height).data));
    c.dataset.state = 'ready';
  }

  private tile(url: string): HTMLImageElement {
    let im = this.tiles.get(url);
    if (im) return im;
    if (this.tiles.size >= TILE_CACHE) this.tiles.delete(this.tiles.keys().next().value!);
    im = new Image();
    im.onload = () => this.schedule();
    im.onerror = () => {
      this.densityCanvas.dataset.errors = String(Number(this.densityCanvas.dataset.errors ?? 0) + 1);
      this.schedule();
    };
    im.src = url;
    this.tiles.set(url, im);
    return im;
  }
}
