// TrafficAnimation (types.ts TrafficAnimationApi): aircraft in motion over a MapLibre map, from the
// server's animation chunks (chunkCache.ts, tsan.ts), drawn by one custom WebGL2 layer (glLayer.ts).
// The playhead is float64 Unix seconds; positions at the playhead are computed on the CPU in float64
// (frame.ts), the tails on the GPU from chunk-relative float32 times.

import type * as maplibregl from 'maplibre-gl';
import { ChunkCache, chunkStartOf, neededChunks } from './chunkCache';
import { legendOf, callsignPrefix } from './colors';
import { compileFilter, type CompiledFilter } from './filter';
import { frameAt, type Frame } from './frame';
import { TrafficGl, metresMatrix } from './glLayer';
import { icaoText, type TsanChunk } from './tsan';
import type {
  AnimationStats, ColorBy, DrawnPosition, Legend, PickedAircraft, TrafficAnimationApi, TrafficAnimationOptions, TrafficFilter,
} from './types';

export const MAX_TAIL_SECONDS = 1800;
/** Pick radius around a glyph (CSS px). */
const PICK_PX = 12;
let nextLayerId = 0;

export class TrafficAnimation implements TrafficAnimationApi {
  readonly layerId = `traffic-animation-${nextLayerId++}`;
  private readonly cache: ChunkCache;
  private gl: TrafficGl | null = null;
  private t = NaN;
  private tail: number;
  private lookahead: number;
  private colorBy: ColorBy;
  private filter: CompiledFilter = compileFilter({});
  private filterKey = '{}';
  private selected: number | null = null;
  private visible = true;
  private frame: Frame | null = null;
  private headings: Float32Array | null = null;
  private hints: Int32Array | null = null;
  private hintsFor: TsanChunk | null = null;
  private frameKey = '';
  private unitMatrix: ArrayLike<number> | null = null;
  private statsCbs: Array<(s: AnimationStats) => void> = [];
  private errorCbs: Array<(e: Error) => void> = [];
  private destroyed = false;
  private readonly layer: maplibregl.CustomLayerInterface;
  private readonly onLoad = () => this.addLayer();

  constructor(
    private readonly map: maplibregl.Map,
    readonly datasetId: string,
    private readonly opts: TrafficAnimationOptions = {},
  ) {
    const d = opts.chunkSeconds ?? 300;
    this.tail = clampTail(opts.tailSeconds ?? 120);
    this.lookahead = (opts.lookaheadChunks ?? 1) * d;
    this.colorBy = opts.colorBy ?? 'altitude';
    const base = opts.baseUrl ?? '';
    const f = opts.fetch ?? ((input: RequestInfo | URL, init?: RequestInit) => window.fetch(input, init));
    this.cache = new ChunkCache({
      url: (s) => `${base}/api/v1/datasets/${encodeURIComponent(datasetId)}/animation?t=${s}&duration=${d}`,
      chunkSeconds: d,
      fetch: f,
      span: opts.span ?? null,
      onChange: () => this.repaint(),
      onError: (_s, e) => {
        for (const cb of this.errorCbs) cb(e);
      },
    });
    const self = this;
    this.layer = {
      id: this.layerId,
      type: 'custom',
      renderingMode: '2d',
      onAdd(_m: maplibregl.Map, gl: WebGLRenderingContext | WebGL2RenderingContext) {
        self.gl = new TrafficGl(gl as WebGL2RenderingContext);
      },
      onRemove() {
        self.gl?.destroy();
        self.gl = null;
      },
      render(_gl: WebGL2RenderingContext | WebGLRenderingContext, args: maplibregl.CustomRenderMethodInput) {
        self.render(args.defaultProjectionData.mainMatrix as unknown as ArrayLike<number>);
      },
    };
    this.addLayer();
  }

  private addLayer() {
    if (this.destroyed || this.map.getLayer(this.layerId)) return;
    try {
      this.map.addLayer(this.layer, this.opts.beforeId && this.map.getLayer(this.opts.beforeId) ? this.opts.beforeId : undefined);
    } catch {
      this.map.once('load', this.onLoad); // the style is not loaded yet
    }
  }

  private repaint() {
    if (!this.destroyed) this.map.triggerRepaint();
  }

  setTime(tUnix: number): void {
    if (!Number.isFinite(tUnix)) throw new RangeError(`setTime: ${tUnix} is not a finite time`);
    this.t = tUnix;
    this.cache.update(tUnix, this.tail, this.lookahead);
    this.repaint();
  }

  time(): number {
    return this.t;
  }

  setTail(seconds: number): void {
    this.tail = clampTail(seconds);
    if (Number.isFinite(this.t)) this.cache.update(this.t, this.tail, this.lookahead);
    this.repaint();
  }

  setLookahead(seconds: number): void {
    this.lookahead = Math.max(0, Number.isFinite(seconds) ? seconds : 0);
    if (Number.isFinite(this.t)) this.cache.update(this.t, this.tail, this.lookahead);
  }

  setColorBy(c: ColorBy): void {
    this.colorBy = c;
    this.repaint();
  }

  legend(): Legend {
    if (this.colorBy !== 'callsign') return legendOf(this.colorBy);
    const counts = new Map<string, number>();
    const fr = this.frame;
    if (fr) for (let i = 0; i < fr.n; i++) {
      const p = callsignPrefix(fr.chunk.callsign[fr.flight[i]!]!);
      counts.set(p, (counts.get(p) ?? 0) + 1);
    }
    return legendOf('callsign', counts);
  }

  setFilter(f: TrafficFilter): void {
    this.filter = compileFilter(f);
    this.filterKey = JSON.stringify(f);
    this.frameKey = '';
    this.repaint();
  }

  setSelected(flightId: number | null): void {
    this.selected = flightId;
    this.repaint();
  }

  setVisible(v: boolean): void {
    this.visible = v;
    if (this.map.getLayer(this.layerId)) this.map.setLayoutProperty(this.layerId, 'visibility', v ? 'visible' : 'none');
    this.repaint();
  }

  /** The frame at the playhead (recomputed when the time, the chunk or the filter changed). */
  private currentFrame(): Frame | null {
    if (!Number.isFinite(this.t)) return null;
    const chunk = this.cache.at(this.t);
    if (!chunk) {
      this.frame = null;
      return null;
    }
    const key = `${this.t}|${this.filterKey}`;
    if (this.frame && this.frame.chunk === chunk && this.frameKey === key) return this.frame;
    if (this.hintsFor !== chunk) {
      this.hints = new Int32Array(chunk.nFlights).fill(-1);
      this.hintsFor = chunk;
    }
    const fr = frameAt(chunk, this.t, this.filter, this.hints!, this.frame);
    // Heading: the track, or the direction of the segment the aircraft is on when the track is unknown.
    if (!this.headings || this.headings.length < fr.flight.length) this.headings = new Float32Array(fr.flight.length);
    const H = this.headings, D = Math.PI / 180;
    for (let i = 0; i < fr.n; i++) {
      const tr = fr.track[i]!;
      if (tr === tr) H[i] = tr * D;
      else {
        const a = fr.sample[i]!, f = fr.flight[i]!;
        const b = a + 1 < chunk.first[f]! + chunk.count[f]! ? a + 1 : a;
        const a0 = b === a ? Math.max(chunk.first[f]!, a - 1) : a;
        H[i] = Math.atan2(chunk.x[b]! - chunk.x[a0]!, chunk.y[b]! - chunk.y[a0]!);
      }
    }
    this.frame = fr;
    this.frameKey = key;
    return fr;
  }

  private render(unitMatrix: ArrayLike<number>) {
    this.unitMatrix = Float64Array.from(unitMatrix);
    const gl = this.gl;
    if (!gl || !this.visible || !Number.isFinite(this.t)) return;
    const chunks = this.cache.loaded();
    gl.retain(chunks);
    const fr = this.currentFrame();
    const canvas = this.map.getCanvas();
    gl.draw({
      t: this.t, tail: this.tail, chunks, frame: fr, headings: this.headings, colorBy: this.colorBy,
      filter: this.filter, filterKey: this.filterKey, selected: this.selected,
      width: canvas.clientWidth, height: canvas.clientHeight, unitMatrix: this.unitMatrix,
    });
    const st = { ...this.cache.stats(), aircraft: fr?.n ?? 0 };
    const c = this.map.getContainer().dataset;
    c.animT = String(this.t);
    c.animAircraft = String(st.aircraft);
    c.animChunks = String(st.chunksInMemory);
    for (const cb of this.statsCbs) cb(st);
  }

  private state(fr: Frame, i: number): PickedAircraft {
    const c = fr.chunk, f = fr.flight[i]!;
    return {
      flightId: c.flightId[f]!, callsign: c.callsign[f]!, icao24: icaoText(c.icao24[f]!),
      lon: fr.lon[i]!, lat: fr.lat[i]!, altM: fr.alt[i]!, speedMs: fr.speed[i]!, trackDeg: fr.track[i]!, vrateMs: fr.vrate[i]!,
    };
  }

  pick(point: { x: number; y: number }): PickedAircraft | null {
    const fr = this.currentFrame();
    if (!fr || !this.unitMatrix) return null;
    const m = metresMatrix(this.unitMatrix, fr.chunk.originX, fr.chunk.originY);
    const canvas = this.map.getCanvas();
    const w = canvas.clientWidth, h = canvas.clientHeight;
    let best = -1, bestD = PICK_PX * PICK_PX;
    for (let i = 0; i < fr.n; i++) {
      const x = fr.x[i]!, y = fr.y[i]!;
      const cw = m[3]! * x + m[7]! * y + m[15]!;
      const sx = ((m[0]! * x + m[4]! * y + m[12]!) / cw + 1) * 0.5 * w;
      const sy = (1 - (m[1]! * x + m[5]! * y + m[13]!) / cw) * 0.5 * h;
      const d = (sx - point.x) ** 2 + (sy - point.y) ** 2;
      if (d <= bestD) {
        bestD = d;
        best = i;
      }
    }
    return best < 0 ? null : this.state(fr, best);
  }

  aircraft(flightId: number): PickedAircraft | null {
    const fr = this.currentFrame();
    if (!fr) return null;
    // Frames are ordered by flight id: binary search.
    let lo = 0, hi = fr.n - 1;
    while (lo <= hi) {
      const mid = (lo + hi) >>> 1;
      const id = fr.chunk.flightId[fr.flight[mid]!]!;
      if (id === flightId) return this.state(fr, mid);
      if (id < flightId) lo = mid + 1;
      else hi = mid - 1;
    }
    return null;
  }

  positionsAt(tUnix: number): DrawnPosition[] {
    const chunk = this.cache.at(tUnix);
    if (!chunk) return [];
    const fr = frameAt(chunk, tUnix, this.filter);
    const out: DrawnPosition[] = new Array(fr.n);
    for (let i = 0; i < fr.n; i++) out[i] = { flightId: chunk.flightId[fr.flight[i]!]!, lon: fr.lon[i]!, lat: fr.lat[i]!, altM: fr.alt[i]! };
    return out;
  }

  ready(tUnix: number): Promise<void> {
    const d = this.cache.chunkSeconds;
    const wanted = new Set(this.cache.wantedStarts());
    const starts = neededChunks(tUnix, this.tail, 0, d, this.opts.span ?? null).filter((s) => s !== chunkStartOf(tUnix, d) + d);
    if (!wanted.has(chunkStartOf(tUnix, d))) return Promise.reject(new Error(`ready(${tUnix}): not at the playhead; call setTime first`));
    return Promise.all(starts.filter((s) => wanted.has(s)).map((s) => this.cache.whenLoaded(s))).then(() => undefined);
  }

  onStats(cb: (s: AnimationStats) => void): void {
    this.statsCbs.push(cb);
  }

  onError(cb: (err: Error) => void): void {
    this.errorCbs.push(cb);
  }

  /** Segment instances the tails drew in the last frame (benchmarks). */
  segmentsDrawn(): number {
    return this.gl?.lastSegments ?? 0;
  }

  destroy(): void {
    if (this.destroyed) return;
    this.destroyed = true;
    this.map.off('load', this.onLoad);
    this.cache.clear();
    if (this.map.getLayer(this.layerId)) this.map.removeLayer(this.layerId);
    this.frame = null;
  }
}

function clampTail(s: number): number {
  return Math.min(MAX_TAIL_SECONDS, Math.max(0, Number.isFinite(s) ? s : 0));
}
