import { describe, expect, it } from 'vitest';
import { readFileSync, readdirSync } from 'node:fs';
import path from 'node:path';
import { Clock, DEFAULT_PLAYBACK, MAX_FRAME_S, SPEEDS, formatSpeed, parsePlayback, stepSpeed, writePlayback, type FrameSource } from './clock';

/** Frames driven by hand: `advance(ms)` moves the time and runs the one pending frame. */
function manualFrames() {
  let now = 1000;
  let pending: ((n: number) => void) | null = null;
  let nextId = 1;
  const src: FrameSource = {
    now: () => now,
    request: (cb) => {
      pending = cb;
      return nextId++;
    },
    cancel: () => {
      pending = null;
    },
  };
  return {
    src,
    pending: () => pending !== null,
    advance(ms: number) {
      now += ms;
      const cb = pending;
      pending = null;
      cb?.(now);
    },
  };
}

// A late instant of 2018-01-01 (the Europe day): 23:59:59.5 UTC.
const LATE = 1514851199.5;
const DAY = { start: 1514764800, end: 1514851200 };

describe('speeds', () => {
  it('are 0.1× then 1, 2, 5 per decade up to 10,000×, each an exact decimal', () => {
    const want = [0.1];
    for (let d = 1; d <= 1000; d *= 10) want.push(d, 2 * d, 5 * d);
    want.push(10000);
    expect(SPEEDS).toEqual(want);
    for (const s of SPEEDS) expect(Number(String(s))).toBe(s);
  });

  it('+ and - walk the steps and stop at the ends', () => {
    const up: number[] = [SPEEDS[0]!];
    while (up.length < 20) up.push(stepSpeed(up[up.length - 1]!, 1));
    expect(up.slice(0, SPEEDS.length)).toEqual([...SPEEDS]);
    expect(up[up.length - 1]).toBe(10000);
    expect(stepSpeed(0.1, -1)).toBe(0.1);
    expect(stepSpeed(1, -1)).toBe(0.1);
    expect(stepSpeed(3, 1)).toBe(5); // 3 is nearest 2 (log scale), one up is 5
    const c = new Clock({ speed: 1 }, manualFrames().src);
    c.faster();
    c.faster();
    expect(c.get().speed).toBe(5);
    c.slower();
    c.slower();
    c.slower();
    expect(c.get().speed).toBe(0.1);
  });

  it('are labelled with their value', () => {
    expect(SPEEDS.map(formatSpeed)).toEqual(['0.1×', '1×', '2×', '5×', '10×', '20×', '50×', '100×', '200×', '500×', '1,000×', '2,000×', '5,000×', '10,000×']);
  });
});

describe('steps and seeking', () => {
  it('±1 s and ±1 min from a late instant of the day are exact', () => {
    const c = new Clock({}, manualFrames().src);
    c.setSpan({ start: DAY.start, end: DAY.end + 3600 });
    c.seek(LATE);
    expect(c.get().t).toBe(LATE);
    c.step(1);
    expect(c.get().t).toBe(1514851200.5);
    c.step(-1);
    c.step(-1);
    expect(c.get().t).toBe(1514851198.5);
    c.step(60);
    expect(c.get().t).toBe(1514851258.5);
    c.step(-60);
    expect(c.get().t).toBe(1514851198.5);
    // In float32 (multiples of 128 s at this size) these steps would all be lost.
    expect(Math.fround(LATE)).not.toBe(LATE);
    expect(Math.fround(LATE + 60)).toBe(Math.fround(LATE));
  });

  it('stays inside the span', () => {
    const c = new Clock({}, manualFrames().src);
    c.setSpan({ start: 100, end: 200 });
    expect(c.get().t).toBe(100); // no instant yet: the span's start
    c.seek(50);
    expect(c.get().t).toBe(100);
    c.seek(250);
    expect(c.get().t).toBe(200);
    c.step(-60);
    expect(c.get().t).toBe(140);
    c.setSpan({ start: 150, end: 300 });
    expect(c.get().t).toBe(150);
  });

  it('notifies subscribers and attached layers with the same instant', () => {
    const c = new Clock({}, manualFrames().src);
    c.setSpan(DAY);
    const seen: number[] = [];
    const layer: number[] = [];
    c.subscribe((s) => seen.push(s.t));
    c.attach({ setTime: (t) => layer.push(t) });
    expect(layer).toEqual([DAY.start]);
    c.seek(LATE);
    c.seek(LATE); // unchanged: no event
    expect(seen).toEqual([LATE]);
    expect(layer).toEqual([DAY.start, LATE]);
  });
});

describe('playback', () => {
  it('advances by real time × speed each frame, in double precision', () => {
    const f = manualFrames();
    const c = new Clock({ speed: 10 }, f.src);
    c.setSpan({ start: DAY.start, end: DAY.end + 3600 });
    c.seek(LATE);
    c.play();
    expect(c.get().playing).toBe(true);
    f.advance(100); // 0.1 s × 10
    expect(c.get().t).toBe(LATE + 1);
    f.advance(50); // 0.05 s × 10
    expect(c.get().t).toBe(LATE + 1.5);
    c.setSpeed(0.1);
    f.advance(200); // 0.2 s × 0.1
    expect(c.get().t).toBeCloseTo(LATE + 1.52, 6);
    c.pause();
    expect(f.pending()).toBe(false);
    const t = c.get().t;
    f.advance(1000);
    expect(c.get().t).toBe(t);
  });

  it('a long frame advances by at most MAX_FRAME_S of real time', () => {
    const f = manualFrames();
    const c = new Clock({ speed: 1000 }, f.src);
    c.setSpan(DAY);
    c.play();
    f.advance(5000);
    expect(c.get().t).toBe(DAY.start + MAX_FRAME_S * 1000);
  });

  it('stops at the span end; play again starts from the span start', () => {
    const f = manualFrames();
    const c = new Clock({ speed: 100 }, f.src);
    c.setSpan({ start: 1000, end: 1030 });
    c.play();
    f.advance(200); // +20 s
    expect(c.get().t).toBe(1020);
    f.advance(200); // would be 1040
    expect(c.get()).toMatchObject({ t: 1030, playing: false });
    expect(f.pending()).toBe(false);
    c.play();
    expect(c.get()).toMatchObject({ t: 1000, playing: true });
  });

  it('does not play without a span', () => {
    const f = manualFrames();
    const c = new Clock({}, f.src);
    c.play();
    expect(c.get().playing).toBe(false);
    expect(f.pending()).toBe(false);
  });
});

describe('the URL', () => {
  it('round-trips a late instant, the speed and the tail exactly', () => {
    for (const at of [LATE, 1514851199.25, DAY.start, 1514800000.123456, 1514851199.9999998]) {
      for (const speed of SPEEDS) {
        const p = new URLSearchParams('dataset=europe&t0=1514764800');
        writePlayback(p, { at, speed, tail: 1800 });
        const back = parsePlayback(new URLSearchParams(p.toString()));
        expect(back).toEqual({ at, speed, tail: 1800 });
      }
    }
    const p = new URLSearchParams();
    writePlayback(p, { at: LATE, speed: 0.1, tail: 0 });
    expect(p.toString()).toBe('at=1514851199.5&speed=0.1&tail=0');
  });

  it('reads ISO 8601 and falls back to the defaults for bad values', () => {
    expect(parsePlayback(new URLSearchParams('at=2018-01-01T23:59:59.5Z')).at).toBe(LATE);
    expect(parsePlayback(new URLSearchParams('at=x&speed=3&tail=-5'))).toEqual({ ...DEFAULT_PLAYBACK, tail: 0 });
    expect(parsePlayback(new URLSearchParams('tail=99999')).tail).toBe(1800);
    expect(parsePlayback(new URLSearchParams(''))).toEqual(DEFAULT_PLAYBACK);
  });

  it('no at: the playback parameters leave the URL', () => {
    const p = new URLSearchParams('at=1&speed=2&tail=3&dataset=x');
    writePlayback(p, { ...DEFAULT_PLAYBACK, at: null });
    expect(p.toString()).toBe('dataset=x');
  });
});

describe('no float32 for time', () => {
  it('the clock and the playback view never make float32 values', () => {
    const dir = path.dirname(new URL(import.meta.url).pathname);
    for (const f of readdirSync(dir).filter((n) => /^(clock|playback\w*|timeBrush)\.ts$/.test(n))) {
      const src = readFileSync(path.join(dir, f), 'utf8');
      expect(src, f).not.toMatch(/Float32Array|Math\.fround/);
    }
  });
});
