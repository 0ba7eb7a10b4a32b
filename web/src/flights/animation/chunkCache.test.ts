import { describe, expect, it } from 'vitest';
import { ChunkCache, chunkStartOf, keepChunk, neededChunks } from './chunkCache';
import { encodeTsan } from './tsanTestEncoder';

const D = 300;
const T0 = 1514764800;

/** A fetch whose answers the test releases; records URLs and aborts. */
function fakeFetch() {
  const calls: Array<{ url: string; signal: AbortSignal; resolve: () => void; fail: (status: number) => void }> = [];
  const fn = ((url: string, init?: RequestInit) =>
    new Promise<Response>((resolve, reject) => {
      const signal = init!.signal!;
      signal.addEventListener('abort', () => reject(new DOMException('aborted', 'AbortError')));
      const start = Number(new URL(url, 'http://x').searchParams.get('t'));
      calls.push({
        url,
        signal,
        resolve: () => resolve(new Response(encodeTsan([], start, D, [0, 0]), { status: 200 })),
        fail: (status) => resolve(new Response(JSON.stringify({ error: 'payload_too_large', detail: 'too many samples', param: 'duration' }), { status })),
      });
    })) as unknown as typeof fetch;
  return { fn, calls };
}

const startOf = (url: string) => Number(new URL(url, 'http://x').searchParams.get('t'));
const tick = () => new Promise((r) => setTimeout(r, 0));

describe('which chunks the playhead needs', () => {
  it('the current chunk, the next, the tail behind (nearest first), then further ahead', () => {
    const t = T0 + 1000; // in chunk T0+900
    expect(neededChunks(t, 600, 900, D).map((s) => (s - T0) / D)).toEqual([3, 4, 2, 1, 5, 6]);
    // No tail: nothing behind. A tail just reaching into the previous chunk needs it.
    expect(neededChunks(t, 0, 0, D).map((s) => (s - T0) / D)).toEqual([3, 4]);
    expect(neededChunks(t, 100.5, 0, D).map((s) => (s - T0) / D)).toEqual([3, 4, 2]);
    expect(neededChunks(t, 100, 0, D).map((s) => (s - T0) / D)).toEqual([3, 4]);
  });

  it('chunk starts are exact multiples at boundaries and late in the day', () => {
    expect(chunkStartOf(T0 + 86399.999, D)).toBe(T0 + 86100);
    expect(chunkStartOf(T0 + 86400, D)).toBe(T0 + 86400);
    expect(chunkStartOf(0.3 * 3, 0.3)).toBeLessThanOrEqual(0.9);
  });

  it('nothing outside the data set is asked for', () => {
    expect(neededChunks(T0 + 10, 1800, 600, D, [T0, T0 + 5000]).map((s) => (s - T0) / D)).toEqual([0, 1, 2]);
  });

  it('keeps exactly the chunks overlapping [t - tail - margin, t + lookahead + d)', () => {
    const t = T0 + 3000;
    const kept = [...Array(30).keys()].map((k) => T0 + k * D).filter((s) => keepChunk(s, t, 600, 300, D));
    expect(kept.map((s) => (s - T0) / D)).toEqual([7, 8, 9, 10, 11]);
  });
});

describe('ChunkCache', () => {
  const url = (s: number) => `/api/v1/datasets/d/animation?t=${s}&duration=${D}`;

  it('requests in order, at most maxInFlight at once, and resolves ready()', async () => {
    const { fn, calls } = fakeFetch();
    const cache = new ChunkCache({ url, chunkSeconds: D, fetch: fn, maxInFlight: 2 });
    cache.update(T0 + 1000, 600, 900);
    expect(calls.map((c) => (startOf(c.url) - T0) / D)).toEqual([3, 4]);
    const ready = cache.whenLoaded(T0 + 900);
    calls[0]!.resolve();
    await ready;
    await tick();
    expect(calls.map((c) => (startOf(c.url) - T0) / D)).toEqual([3, 4, 2]);
    expect(cache.at(T0 + 1000)?.tStart).toBe(T0 + 900);
  });

  it('ready() waits for a chunk that waits for a fetch slot', async () => {
    const { fn, calls } = fakeFetch();
    const cache = new ChunkCache({ url, chunkSeconds: D, fetch: fn, maxInFlight: 1 });
    cache.update(T0 + 1000, 900, 0); // wants 3, 4, 2, 1, 0; one fetch at a time
    const tailChunk = cache.whenLoaded(T0); // not started yet
    let done = false;
    void tailChunk.then(() => (done = true));
    for (let i = 0; i < 5; i++) {
      expect(done).toBe(false);
      calls[i]!.resolve();
      await tick();
      await tick();
    }
    expect(calls.map((c) => (startOf(c.url) - T0) / D)).toEqual([3, 4, 2, 1, 0]);
    expect(done).toBe(true);
  });

  it('scrubbing aborts the fetches it supersedes and drops chunks out of range', async () => {
    const { fn, calls } = fakeFetch();
    const cache = new ChunkCache({ url, chunkSeconds: D, fetch: fn, maxInFlight: 3 });
    cache.update(T0 + 1100, 120, 0);
    for (const c of calls) c.resolve();
    await tick();
    await tick();
    expect(cache.stats().chunksInMemory).toBe(2);
    cache.update(T0 + 50000, 120, 0); // a jump: the old ones go, new ones start
    await tick();
    expect(cache.stats().chunksInMemory).toBe(0);
    const pending = calls.slice(2);
    expect(pending.map((c) => startOf(c.url))).toEqual([chunkStartOf(T0 + 50000, D), chunkStartOf(T0 + 50000, D) + D]);
    cache.update(T0 + 20000, 120, 0); // scrub again before they arrive
    expect(pending.every((c) => c.signal.aborted)).toBe(true);
    expect(calls.slice(4).map((c) => startOf(c.url))).toEqual([chunkStartOf(T0 + 20000, D), chunkStartOf(T0 + 20000, D) + D]);
    for (const c of calls) c.resolve(); // late answers of aborted fetches are ignored
    await tick();
    await tick();
    expect(cache.loaded().map((c) => c.tStart)).toEqual([chunkStartOf(T0 + 20000, D), chunkStartOf(T0 + 20000, D) + D]);
  });

  it('memory stays bounded over a whole day of playback', async () => {
    const { fn, calls } = fakeFetch();
    const cache = new ChunkCache({ url, chunkSeconds: D, fetch: fn, maxInFlight: 4 });
    let maxChunks = 0, answered = 0;
    for (let t = T0; t < T0 + 86400; t += 7.5) {
      cache.update(t, 1800, 600);
      // The server answers everything asked (the cache asks for more as answers arrive).
      for (let round = 0; round < 8 && answered < calls.length; round++) {
        while (answered < calls.length) calls[answered++]!.resolve();
        await tick();
        await tick();
      }
      maxChunks = Math.max(maxChunks, cache.stats().chunksInMemory);
      // Everything drawn now is there: the chunk of t and the tail's chunks.
      if ((t - T0) % 3000 === 0) for (const s of neededChunks(t, 1800, 0, D)) expect(cache.get(s)).not.toBeNull();
    }
    // tail 1800 s + margin 300 s + current + lookahead 600 s + next: at most 12 chunks of 300 s.
    expect(maxChunks).toBeLessThanOrEqual(Math.ceil((1800 + 300 + 600 + 2 * 300) / 300) + 1);
    expect(maxChunks).toBeGreaterThanOrEqual(8);
    // Each chunk of the day was fetched once (playback never refetches what it keeps).
    const starts = calls.map((c) => startOf(c.url));
    expect(new Set(starts).size).toBe(starts.length);
  });

  it('an API error rejects ready() with the server detail and is not refetched while kept', async () => {
    const { fn, calls } = fakeFetch();
    const errors: string[] = [];
    const cache = new ChunkCache({ url, chunkSeconds: D, fetch: fn, maxInFlight: 1, onError: (_s, e) => errors.push(e.message) });
    cache.update(T0 + 10, 0, 0);
    const ready = cache.whenLoaded(T0);
    calls[0]!.fail(413);
    await expect(ready).rejects.toThrow('too many samples');
    expect(errors).toEqual(['too many samples']);
    cache.update(T0 + 11, 0, 0);
    await tick();
    expect(calls.filter((c) => startOf(c.url) === T0).length).toBe(1);
  });
});
