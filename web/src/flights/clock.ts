// The flight dashboard's one clock: the instant every time-dependent layer shows (the moving aircraft,
// the bundles that follow the clock, a congestion panel's volumes, the cursor on the time histogram).
//
// Layers do not keep their own time: they subscribe to the clock (`subscribe`, or `attach` for anything
// with a `setTime(t)`), and read `get().t`. Scrubbing, stepping, the keyboard and playback all change the
// clock, and every subscriber sees the same instant in the same frame.
//
// Time is Unix seconds in a JavaScript number (IEEE-754 double): at 1.5e9 s its resolution is 2^-22 s
// (about 0.24 µs), so half-seconds, steps of 1 s and 60 s, and every speed step stay exact. Nothing here
// converts time to float32 (whose resolution at 1.5e9 s is 128 s); a layer that needs float32 on the GPU
// subtracts a nearby origin in double first.
//
// Playback is frame-driven: each animation frame advances the instant by (real seconds since the last
// frame, from performance.now()) × speed. It stops (pauses) at the end of the span; play at the end
// starts again from the span's start.

/** Playback speeds (× real time): 0.1× slow motion, then 1, 2, 5 per decade up to 10,000×. */
export const SPEEDS: readonly number[] = [0.1, 1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, 5000, 10000];
export const DEFAULT_SPEED = 100;
/** Trail tails: 0 (glyphs only) to 30 min, in seconds. */
export const MAX_TAIL_S = 1800;
export const DEFAULT_TAIL_S = 120;
/** The small and the large step (seconds): ←/→ and Shift+←/→. */
export const STEP_SMALL_S = 1;
export const STEP_LARGE_S = 60;
/**
 * The longest real time one frame may advance the clock by (seconds): after a hidden tab or a long GC
 * pause the next frame would otherwise jump by the whole pause × speed.
 */
export const MAX_FRAME_S = 0.25;

/** A time range [start, end] in Unix seconds that the clock stays in. */
export interface ClockSpan {
  start: number;
  end: number;
}

export interface ClockState {
  /** The instant, Unix seconds (a double; may have a fraction). */
  t: number;
  playing: boolean;
  /** One of SPEEDS. */
  speed: number;
  /** The range the instant is kept in (the time window, or the data set's range); null before one is known. */
  span: ClockSpan | null;
}

export type ClockListener = (s: ClockState, prev: ClockState) => void;

/** Anything drawn at the clock's instant. */
export interface TimeLayer {
  setTime(t: number): void;
}

/** The frame source: the browser's by default, a manual one in the unit tests. */
export interface FrameSource {
  now(): number;
  request(cb: (now: number) => void): number;
  cancel(id: number): void;
}

const browserFrames = (): FrameSource => ({
  now: () => performance.now(),
  request: (cb) => requestAnimationFrame(cb),
  cancel: (id) => cancelAnimationFrame(id),
});

/** The speed step `dir` steps (±1) away from `speed` (the nearest step first when `speed` is not one). */
export function stepSpeed(speed: number, dir: number): number {
  let i = SPEEDS.indexOf(speed);
  if (i < 0) i = nearestSpeedIndex(speed);
  return SPEEDS[Math.min(SPEEDS.length - 1, Math.max(0, i + Math.sign(dir)))]!;
}

function nearestSpeedIndex(speed: number): number {
  let best = 0;
  for (let i = 1; i < SPEEDS.length; i++) {
    if (Math.abs(Math.log(SPEEDS[i]! / speed)) < Math.abs(Math.log(SPEEDS[best]! / speed))) best = i;
  }
  return best;
}

/** "0.1×", "1×", "10,000×". */
export function formatSpeed(speed: number): string {
  return `${speed.toLocaleString('en-US', { maximumFractionDigits: 1 })}×`;
}

function clampTo(t: number, span: ClockSpan | null): number {
  if (!span) return t;
  return Math.min(span.end, Math.max(span.start, t));
}

export class Clock {
  private state: ClockState;
  private readonly listeners = new Set<ClockListener>();
  private readonly frames: FrameSource;
  private frameId = 0;
  private lastNow = 0;

  constructor(initial: Partial<ClockState> = {}, frames: FrameSource = browserFrames()) {
    this.frames = frames;
    this.state = { t: NaN, playing: false, speed: DEFAULT_SPEED, span: null, ...initial };
    if (!SPEEDS.includes(this.state.speed)) this.state.speed = SPEEDS[nearestSpeedIndex(this.state.speed)]!;
    this.state.playing = false; // playback starts with play()
  }

  get(): ClockState {
    return this.state;
  }

  /** Calls `l` on every change (not at once); returns the unsubscribe function. */
  subscribe(l: ClockListener): () => void {
    this.listeners.add(l);
    return () => this.listeners.delete(l);
  }

  /** Keeps a layer at the clock's instant: sets it now (when the instant is known) and on every change of t. */
  attach(layer: TimeLayer): () => void {
    if (Number.isFinite(this.state.t)) layer.setTime(this.state.t);
    return this.subscribe((s, prev) => {
      if (s.t !== prev.t && Number.isFinite(s.t)) layer.setTime(s.t);
    });
  }

  private set(patch: Partial<ClockState>) {
    const prev = this.state;
    const next = { ...prev, ...patch };
    if (next.t === prev.t && next.playing === prev.playing && next.speed === prev.speed && next.span === prev.span) return;
    this.state = next;
    for (const l of this.listeners) l(next, prev);
  }

  /**
   * The range the instant is kept in. An instant outside it (or none yet) moves to the nearest end
   * (to the start when there was none), so a new window starts playback at its start.
   */
  setSpan(span: ClockSpan | null): void {
    const t = this.state.t;
    const nt = span ? (Number.isFinite(t) ? clampTo(t, span) : span.start) : t;
    const playing = this.state.playing && !(span && nt >= span.end);
    this.set({ span, t: nt, playing });
    if (!playing) this.stopFrames();
  }

  /** Jumps to t (kept in the span). Playback continues from there when it runs. */
  seek(t: number): void {
    if (!Number.isFinite(t)) return;
    this.set({ t: clampTo(t, this.state.span) });
  }

  /** Moves the instant by dt seconds (kept in the span). */
  step(dt: number): void {
    if (!Number.isFinite(this.state.t)) return;
    this.seek(this.state.t + dt);
  }

  setSpeed(speed: number): void {
    this.set({ speed: SPEEDS.includes(speed) ? speed : SPEEDS[nearestSpeedIndex(speed)]! });
  }

  faster(): void {
    this.setSpeed(stepSpeed(this.state.speed, 1));
  }

  slower(): void {
    this.setSpeed(stepSpeed(this.state.speed, -1));
  }

  play(): void {
    const s = this.state;
    if (s.playing || !s.span) return;
    // At the end, play starts over from the span's start.
    const t = !Number.isFinite(s.t) || s.t >= s.span.end ? s.span.start : s.t;
    this.set({ playing: true, t });
    this.lastNow = this.frames.now();
    this.frameId = this.frames.request((now) => this.tick(now));
  }

  pause(): void {
    this.stopFrames();
    this.set({ playing: false });
  }

  toggle(): void {
    if (this.state.playing) this.pause();
    else this.play();
  }

  private stopFrames() {
    if (this.frameId) this.frames.cancel(this.frameId);
    this.frameId = 0;
  }

  private tick(now: number) {
    this.frameId = 0;
    const s = this.state;
    if (!s.playing || !s.span) return;
    const dtReal = Math.min(MAX_FRAME_S, Math.max(0, (now - this.lastNow) / 1000));
    this.lastNow = now;
    const t = s.t + dtReal * s.speed;
    if (t >= s.span.end) {
      this.set({ t: s.span.end, playing: false });
      return;
    }
    this.set({ t });
    if (this.state.playing) this.frameId = this.frames.request((n) => this.tick(n));
  }

  /** Stops the frame loop and forgets every listener. */
  destroy(): void {
    this.stopFrames();
    this.listeners.clear();
  }
}

// ---------- the URL ----------
// The flight dashboard's hash is its own query string (route.ts): `at` (the instant, Unix seconds as the
// shortest decimal that reads back to the same double, or ISO 8601 when typed by hand), `speed` (one of
// SPEEDS) and `tail` (seconds, 0 … MAX_TAIL_S). `at` present means the playback view is open.

export interface PlaybackParams {
  at: number | null;
  speed: number;
  tail: number;
}

export const DEFAULT_PLAYBACK: PlaybackParams = { at: null, speed: DEFAULT_SPEED, tail: DEFAULT_TAIL_S };

/** Reads `at`, `speed` and `tail`; a missing or invalid value gives the default. */
export function parsePlayback(q: URLSearchParams): PlaybackParams {
  const out = { ...DEFAULT_PLAYBACK };
  const at = q.get('at');
  if (at !== null && at.trim() !== '') {
    const n = /^[+-]?(\d+\.?\d*|\.\d+)(e[+-]?\d+)?$/i.test(at.trim()) ? Number(at) : Date.parse(at) / 1000;
    if (Number.isFinite(n)) out.at = n;
  }
  const speed = Number(q.get('speed'));
  if (q.has('speed') && SPEEDS.includes(speed)) out.speed = speed;
  const tail = Number(q.get('tail'));
  if (q.has('tail') && q.get('tail')!.trim() !== '' && Number.isFinite(tail)) out.tail = Math.min(MAX_TAIL_S, Math.max(0, tail));
  return out;
}

/** Writes `at`, `speed` and `tail` into p (at: String(t), which reads back to the same double). */
export function writePlayback(p: URLSearchParams, v: PlaybackParams): void {
  if (v.at === null || !Number.isFinite(v.at)) {
    p.delete('at');
    p.delete('speed');
    p.delete('tail');
    return;
  }
  p.set('at', String(v.at));
  p.set('speed', String(v.speed));
  p.set('tail', String(v.tail));
}
