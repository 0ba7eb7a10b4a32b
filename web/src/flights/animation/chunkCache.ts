// The animation chunks in memory: which chunks the playhead needs, fetching them in that order, and
// dropping the rest, so memory is bounded by the tail, the lookahead and the chunk length whatever the
// window's length.
//
// Needed at playhead t with tail T, lookahead L and chunk length D (aligned starts k·D):
//   1. the chunk holding t (what is drawn now);
//   2. the next chunk ahead (playback moves into it next);
//   3. the chunks behind that hold the tail [t - T, t), nearest first;
//   4. further chunks ahead up to t + L.
// Kept: every chunk that overlaps [t - T - margin, t + L + D) (margin = one chunk, so that a small step
// back does not refetch); every other chunk is dropped, and a fetch in progress for a chunk no longer
// needed is aborted (scrubbing supersedes it). At most `maxInFlight` fetches run at once.
//
// Revalidation is the browser's: the server sends a strong ETag and Cache-Control private/max-age, so
// fetch() answers a refetched chunk from the HTTP cache or revalidates it with If-None-Match (304).

import { decodeTsan, type TsanChunk } from './tsan';
import { errorFromResponse } from '../../api/client';

export interface ChunkCacheOptions {
  /** The route's URL of the chunk starting at `start` (Unix seconds). */
  url(start: number): string;
  chunkSeconds: number;
  fetch: typeof fetch;
  /** Parallel fetches (default 3). */
  maxInFlight?: number;
  /** The dataset's time span: chunks wholly outside [tMin, tMax] are never fetched. */
  span?: [number, number] | null;
  /** Called when a chunk arrives or is dropped. */
  onChange?: () => void;
  /** Called when a fetch fails (not when it is aborted). */
  onError?: (start: number, err: Error) => void;
}

interface Entry {
  start: number;
  state: 'loading' | 'ready' | 'error';
  chunk: TsanChunk | null;
  ctrl: AbortController | null;
  error: Error | null;
  waiters: Array<{ resolve: () => void; reject: (e: Error) => void }>;
}

/** Floor of t to a multiple of d, robust to float64 rounding at a boundary. */
export function chunkStartOf(t: number, d: number): number {
  let s = Math.floor(t / d) * d;
  if (s > t) s -= d;
  else if (s + d <= t) s += d;
  return s;
}

/** The chunk starts the playhead needs, in fetch order (see the file comment). */
export function neededChunks(t: number, tail: number, lookahead: number, d: number, span?: [number, number] | null): number[] {
  const out: number[] = [];
  const add = (s: number) => {
    if (span && (s + d <= span[0] || s > span[1])) return;
    if (!out.includes(s)) out.push(s);
  };
  const cur = chunkStartOf(t, d);
  add(cur);
  add(cur + d);
  for (let s = cur - d; s + d > t - tail; s -= d) add(s);
  for (let s = cur + 2 * d; s < t + lookahead; s += d) add(s);
  return out;
}

/** Whether chunk `s` is kept at playhead t (overlaps [t - tail - margin, t + lookahead + d)). */
export function keepChunk(s: number, t: number, tail: number, lookahead: number, d: number): boolean {
  return s + d > t - tail - d && s < t + Math.max(lookahead, 0) + d;
}

export class ChunkCache {
  private readonly entries = new Map<number, Entry>();
  /** Waiters for chunks that are wanted but not started yet (the in-flight cap). */
  private readonly early = new Map<number, Entry['waiters']>();
  private wanted: number[] = [];
  private t = NaN;
  private tail = 0;
  private lookahead = 0;
  private readonly maxInFlight: number;

  constructor(private readonly opts: ChunkCacheOptions) {
    this.maxInFlight = opts.maxInFlight ?? 3;
  }

  get chunkSeconds(): number {
    return this.opts.chunkSeconds;
  }

  /** Moves the playhead: drops and aborts what is no longer needed, then starts fetches in order. */
  update(t: number, tail: number, lookahead: number): void {
    this.t = t;
    this.tail = tail;
    this.lookahead = lookahead;
    const d = this.opts.chunkSeconds;
    this.wanted = neededChunks(t, tail, lookahead, d, this.opts.span);
    let dropped = false;
    for (const [s, e] of this.entries) {
      // A failed chunk stays (failed) while it is kept, so a playing clock does not refetch it every
      // frame; it is retried once the playhead has left it and comes back.
      if (keepChunk(s, t, tail, lookahead, d)) continue;
      e.ctrl?.abort();
      for (const w of e.waiters) w.reject(new DOMException('The chunk is no longer needed', 'AbortError'));
      this.entries.delete(s);
      dropped = true;
    }
    for (const [s, ws] of this.early) {
      if (this.wanted.includes(s)) continue;
      for (const w of ws) w.reject(new DOMException('The chunk is no longer needed', 'AbortError'));
      this.early.delete(s);
    }
    this.pump();
    if (dropped) this.opts.onChange?.();
  }

  private inFlight(): number {
    let n = 0;
    for (const e of this.entries.values()) if (e.state === 'loading') n++;
    return n;
  }

  private pump() {
    let n = this.inFlight();
    for (const s of this.wanted) {
      if (n >= this.maxInFlight) break;
      if (this.entries.has(s)) continue;
      this.load(s);
      n++;
    }
  }

  private load(start: number) {
    const ctrl = new AbortController();
    const e: Entry = { start, state: 'loading', chunk: null, ctrl, error: null, waiters: this.early.get(start) ?? [] };
    this.early.delete(start);
    this.entries.set(start, e);
    void this.opts
      .fetch(this.opts.url(start), { signal: ctrl.signal })
      .then(async (res) => {
        if (!res.ok) throw await errorFromResponse(res);
        return decodeTsan(await res.arrayBuffer());
      })
      .then(
        (chunk) => {
          if (this.entries.get(start) !== e) return;
          e.state = 'ready';
          e.chunk = chunk;
          e.ctrl = null;
          for (const w of e.waiters) w.resolve();
          e.waiters = [];
          this.opts.onChange?.();
          this.pump();
        },
        (err: unknown) => {
          if (this.entries.get(start) !== e) return; // dropped (aborted): not news
          const error = err instanceof Error ? err : new Error(String(err));
          e.state = 'error';
          e.error = error;
          e.ctrl = null;
          for (const w of e.waiters) w.reject(error);
          e.waiters = [];
          this.opts.onError?.(start, error);
          this.pump();
        },
      );
  }

  /** The loaded chunk starting at `start`, or null. */
  get(start: number): TsanChunk | null {
    return this.entries.get(start)?.chunk ?? null;
  }

  /** The loaded chunk holding t, or null. */
  at(t: number): TsanChunk | null {
    return this.get(chunkStartOf(t, this.opts.chunkSeconds));
  }

  /** Loaded chunks, ordered by start. */
  loaded(): TsanChunk[] {
    return [...this.entries.values()]
      .filter((e) => e.chunk)
      .sort((a, b) => a.start - b.start)
      .map((e) => e.chunk!);
  }

  /** Resolves when chunk `start` is loaded (it must be wanted: call update first); rejects on its error or drop. */
  whenLoaded(start: number): Promise<void> {
    const e = this.entries.get(start);
    if (!e) {
      if (this.opts.span && (start + this.opts.chunkSeconds <= this.opts.span[0] || start > this.opts.span[1])) return Promise.resolve();
      if (!this.wanted.includes(start)) return Promise.reject(new Error(`chunk ${start} is not wanted at the playhead`));
      // Wanted, waiting for a fetch slot.
      return new Promise((resolve, reject) => {
        const ws = this.early.get(start) ?? [];
        ws.push({ resolve, reject });
        this.early.set(start, ws);
      });
    }
    if (e.state === 'ready') return Promise.resolve();
    if (e.state === 'error') return Promise.reject(e.error!);
    return new Promise((resolve, reject) => e.waiters.push({ resolve, reject }));
  }

  /** Chunk starts currently wanted, in fetch order. */
  wantedStarts(): number[] {
    return [...this.wanted];
  }

  stats(): { chunksInMemory: number; bytesInMemory: number; pending: number } {
    let chunks = 0, bytes = 0, pending = 0;
    for (const e of this.entries.values()) {
      if (e.chunk) {
        chunks++;
        bytes += e.chunk.byteLength;
      } else if (e.state === 'loading') pending++;
    }
    return { chunksInMemory: chunks, bytesInMemory: bytes, pending };
  }

  /** Aborts every fetch and forgets every chunk. */
  clear(): void {
    for (const e of this.entries.values()) {
      e.ctrl?.abort();
      for (const w of e.waiters) w.reject(new DOMException('The cache was cleared', 'AbortError'));
    }
    this.entries.clear();
    for (const ws of this.early.values()) for (const w of ws) w.reject(new DOMException('The cache was cleared', 'AbortError'));
    this.early.clear();
    this.wanted = [];
    this.opts.onChange?.();
  }

  /** The playhead last given to update(). */
  playhead(): { t: number; tail: number; lookahead: number } {
    return { t: this.t, tail: this.tail, lookahead: this.lookahead };
  }
}
