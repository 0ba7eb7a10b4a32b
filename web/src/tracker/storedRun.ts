// A stored tracker run as the tracker dashboard's frame source: the same operations as a replay viewer
// (play, pause, seek, step, speed), but the cursor is local. The run's frame records are fetched in pages
// (GET /api/v1/runs/{run}/frames, at most 1000 a page, the page holding the cursor first) into the
// FrameStore, and the pictures of the frame under the cursor come from the video
// (GET /api/v1/videos/{video}/frames/{i}/depth.png and amplitude.png). Playing advances the cursor on a
// timer at the video's fps × speed; while pictures load, only the newest cursor frame is fetched.

import { ApiError, isAbort } from '../api/client';
import { trackerApi, type RunFramesPage } from '../api/replay';
import type { FrameRecord, FrameTruth } from '../api/trackerLog';
import { SPEED_MAX, SPEED_MIN, type PlayerState, type ReplayOp } from '../api/trackerTypes';
import type { FrameStore } from './frameStore';

/** What feeds the tracker dashboard's player: a replay's WebSocket viewer or a stored run. */
export interface FrameSource {
  /** Applies a transport operation; false when it cannot (not connected). */
  send(op: ReplayOp): boolean;
  close(): void;
}

/** One frame to draw: pictures (PNG bytes) with the tracker record and truth of that frame, if any. */
export interface ShownFrame {
  index: number;
  depthPng: Uint8Array | null;
  amplitudePng: Uint8Array | null;
  frame: FrameRecord | null;
  truth: FrameTruth | null;
}

/** Frame records per request (the route's kMaxRunFramesPerPage is 1000). */
export const RUN_PAGE = 1000;

/**
 * Page ranges [from, to) of log positions covering [0, total), at most `size` each, aligned to `size`;
 * the page holding position `at` comes first, then the following pages, then the earlier ones.
 */
export function pagePlan(total: number, size: number, at = 0): [number, number][] {
  if (!(total > 0) || !(size > 0)) return [];
  const pages: [number, number][] = [];
  for (let f = 0; f < total; f += size) pages.push([f, Math.min(total, f + size)]);
  const k = Math.max(0, Math.min(pages.length - 1, Math.floor(Math.max(0, at) / size)));
  return [...pages.slice(k), ...pages.slice(0, k)];
}

function clamp(v: number, lo: number, hi: number): number {
  return Math.max(lo, Math.min(hi, v));
}

/** The local player's state after an operation on a video of `frames` frames. */
export function applyOp(s: PlayerState, op: ReplayOp, frames: number): PlayerState {
  const last = Math.max(0, frames - 1);
  switch (op.op) {
    case 'play':
      // Playing from the last frame starts over.
      return { ...s, playing: frames > 1, frame: s.frame >= last ? 0 : s.frame };
    case 'pause':
      return { ...s, playing: false };
    case 'seek':
      return Number.isFinite(op.frame) ? { ...s, frame: clamp(Math.round(op.frame), 0, last) } : s;
    case 'step':
      return Number.isFinite(op.delta) ? { ...s, playing: false, frame: clamp(s.frame + Math.round(op.delta), 0, last) } : s;
    case 'speed':
      return Number.isFinite(op.value) && op.value > 0 ? { ...s, speed: clamp(op.value, SPEED_MIN, SPEED_MAX) } : s;
    default:
      return s;
  }
}

/** The frame a player started at `from` reaches after `elapsedMs` at `fps` × `speed`. */
export function playFrame(from: number, elapsedMs: number, fps: number, speed: number): number {
  const rate = Number.isFinite(fps) && fps > 0 ? fps : 30;
  return from + Math.floor((Math.max(0, elapsedMs) / 1000) * rate * speed);
}

export interface StoredRunInfo {
  run: string;
  video: string;
  /** Frames of the video (the cursor's range). */
  frames: number;
  fps: number;
  /** Frame records of the run (log positions), when known from its summary. */
  logFrames: number | null;
  /** Whether the video has ground truth (fetched per frame when the run does not store it). */
  videoHasTruth: boolean;
  colormap: string;
  /** The video's colour range, mm (GET /api/v1/videos/{v} depth_range_mm), when the store has it. */
  depthRange?: [number, number];
}

export interface StoredRunHandlers {
  onState(s: PlayerState): void;
  onFrame(f: ShownFrame): void;
  /** A page of records arrived (the store grew). */
  onPage(loaded: number, total: number): void;
  onError(message: string): void;
}

export class StoredRunSource implements FrameSource {
  private state: PlayerState;
  private readonly ctrl = new AbortController();
  private closed = false;
  private timer: number | undefined;
  private playFrom = 0;
  private playT0 = 0;
  /** Frame wanted on screen, and frame last drawn with its pictures. */
  private want = -1;
  private shown: ShownFrame | null = null;
  private fetching = false;
  /** Null until the first page says whether the run stores ground truth. */
  private runHasTruth: boolean | null = null;
  private readonly videoTruth = new Map<number, FrameTruth | null>();

  constructor(
    readonly info: StoredRunInfo,
    private readonly store: FrameStore,
    private readonly handlers: StoredRunHandlers,
  ) {
    this.state = { playing: false, frame: 0, speed: 1 };
  }

  get frame(): number {
    return this.state.frame;
  }

  /**
   * Shows `frame` (clamped; null: the run's first frame, once known) and loads the run's records, the
   * page around the cursor first.
   */
  start(frame: number | null): void {
    this.state = applyOp(this.state, { op: 'seek', frame: frame ?? 0 }, this.info.frames);
    this.handlers.onState(this.state);
    if (frame !== null) this.request(this.state.frame);
    void this.loadPages(frame === null);
  }

  send(op: ReplayOp): boolean {
    if (this.closed) return false;
    const before = this.state;
    this.state = applyOp(before, op, this.info.frames);
    if (this.state.playing && (!before.playing || op.op === 'seek' || op.op === 'speed' || op.op === 'play')) {
      this.playFrom = this.state.frame;
      this.playT0 = performance.now();
      window.clearTimeout(this.timer);
      this.timer = window.setTimeout(this.tick, this.interval());
    } else if (!this.state.playing) window.clearTimeout(this.timer);
    this.handlers.onState(this.state);
    this.request(this.state.frame);
    return true;
  }

  close(): void {
    this.closed = true;
    window.clearTimeout(this.timer);
    this.ctrl.abort();
  }

  private interval(): number {
    const fps = this.info.fps > 0 ? this.info.fps : 30;
    return Math.max(15, 1000 / (fps * this.state.speed));
  }

  private readonly tick = () => {
    if (this.closed || !this.state.playing) return;
    const last = this.info.frames - 1;
    let f = playFrame(this.playFrom, performance.now() - this.playT0, this.info.fps, this.state.speed);
    const end = f >= last;
    if (end) f = last;
    if (f !== this.state.frame || end) {
      this.state = { ...this.state, frame: f, playing: !end };
      this.handlers.onState(this.state);
      this.request(f);
    }
    if (!end) this.timer = window.setTimeout(this.tick, this.interval());
  };

  /**
   * Colours depth with one range for the whole video (`range`, the store's depth_range_mm) or, with
   * undefined, each frame with its own 2nd–98th percentiles (the server's default); the frame on screen
   * is fetched again.
   */
  setDepthRange(range: [number, number] | undefined): void {
    if (range) this.info.depthRange = range;
    else delete this.info.depthRange;
    const f = this.shown?.index ?? this.want;
    this.shown = null;
    if (f >= 0) this.request(f);
  }

  /** Puts `frame` on screen once its pictures are in (only the newest wanted frame is fetched). */
  private request(frame: number) {
    this.want = frame;
    if (!this.fetching) void this.pump();
  }

  private async pump() {
    this.fetching = true;
    const { video, colormap, depthRange } = this.info;
    const signal = this.ctrl.signal;
    try {
      while (!this.closed && this.want >= 0 && this.want !== this.shown?.index) {
        const f = this.want;
        const [depthPng, amplitudePng, truth] = await Promise.all([
          trackerApi.framePng(video, f, 'depth', colormap, signal, depthRange),
          trackerApi.framePng(video, f, 'amplitude', undefined, signal),
          this.truthOf(f, signal),
        ]);
        if (this.closed) return;
        this.shown = { index: f, depthPng, amplitudePng, frame: this.store.records[f] ?? null, truth };
        this.handlers.onFrame(this.shown);
      }
    } catch (e) {
      if (!isAbort(e) && !this.closed) this.handlers.onError(`Could not load frame ${this.want}: ${e instanceof ApiError ? e.detail : String(e)}`);
    } finally {
      this.fetching = false;
    }
  }

  /** The truth of a frame: the run's when it stores truth, else the video's (fetched once per frame). */
  private async truthOf(f: number, signal: AbortSignal): Promise<FrameTruth | null> {
    const stored = this.store.truth[f];
    if (stored) return stored;
    if (!this.info.videoHasTruth || this.runHasTruth === true) return stored ?? null;
    if (this.videoTruth.has(f)) return this.videoTruth.get(f) ?? null;
    const t = await trackerApi.videoFrameTruth(this.info.video, f, signal);
    this.videoTruth.set(f, t);
    return t;
  }

  private async loadPages(toFirst: boolean) {
    const { run } = this.info;
    const signal = this.ctrl.signal;
    try {
      // The first page tells the run's first video frame (a run may cover part of its video), so the
      // page holding the cursor can come next.
      const n = this.info.logFrames;
      const first = await trackerApi.runFramesPage(run, 0, n !== null && n > 0 ? Math.min(n, RUN_PAGE) : null, signal);
      const total = Number.isFinite(first.total) ? first.total : (n ?? first.to);
      this.take(first, total);
      const firstIndex = first.items[0]?.frame.index ?? 0;
      if (toFirst && !this.closed) this.send({ op: 'seek', frame: firstIndex });
      const plan = pagePlan(total, RUN_PAGE, this.state.frame - firstIndex).filter(([from]) => from !== first.from);
      for (const [from, to] of plan) {
        if (this.closed) return;
        this.take(await trackerApi.runFramesPage(run, from, to, signal), total);
      }
    } catch (e) {
      if (!isAbort(e) && !this.closed) this.handlers.onError(`Could not load the run's frames: ${e instanceof ApiError ? e.detail : String(e)}`);
    }
  }

  private take(page: RunFramesPage, total: number) {
    if (this.closed) return;
    if (this.runHasTruth === null) this.runHasTruth = page.hasTruth;
    this.store.putMany(page.items);
    this.handlers.onPage(this.store.knownCount, total);
    // The frame on screen may have been drawn before its record arrived: draw it again with it.
    const s = this.shown;
    if (s && !s.frame && this.store.records[s.index]) {
      this.shown = { ...s, frame: this.store.records[s.index]!, truth: s.truth ?? this.store.truth[s.index] ?? null };
      this.handlers.onFrame(this.shown);
    }
  }
}
