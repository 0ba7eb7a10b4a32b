import { describe, expect, it } from 'vitest';
import { decodeRunFramesPage } from '../api/replay';
import { FrameStore } from './frameStore';
import { parseTrackerRoute, trackerRunHash } from './route';
import { applyOp, pagePlan, playFrame, RUN_PAGE } from './storedRun';

describe('stored run route', () => {
  it('parses run and frame', () => {
    expect(parseTrackerRoute('#tracker?run=r12&frame=37')).toEqual({ replay: null, run: 'r12', frame: 37, video: null, depthPerFrame: false });
    expect(parseTrackerRoute('#tracker?replay=replay-1')).toEqual({ replay: 'replay-1', run: null, frame: null, video: null, depthPerFrame: false });
    expect(parseTrackerRoute('#tracker?replay=replay-1&frame=12')).toMatchObject({ replay: 'replay-1', frame: 12 });
    expect(parseTrackerRoute(trackerRunHash('r1', 5, true))).toMatchObject({ run: 'r1', frame: 5, depthPerFrame: true });
    expect(parseTrackerRoute('#tracker').run).toBeNull();
    expect(parseTrackerRoute('#runs?run=r1&frame=3').run).toBeNull();
  });
  it('ignores a malformed frame', () => {
    for (const f of ['-1', '1.5', 'x', '', '1e3', '99999999999999999999']) expect(parseTrackerRoute(`#tracker?run=r1&frame=${f}`).frame).toBeNull();
    expect(parseTrackerRoute('#tracker?run=%20&frame=2').run).toBeNull();
  });
  it('round-trips through trackerRunHash', () => {
    expect(trackerRunHash('r7', 12)).toBe('#tracker?run=r7&frame=12');
    expect(trackerRunHash('r7')).toBe('#tracker?run=r7');
    expect(trackerRunHash('r7', -3)).toBe('#tracker?run=r7');
    const r = parseTrackerRoute(trackerRunHash('a b&c', 0));
    expect(r.run).toBe('a b&c');
    expect(r.frame).toBe(0);
  });
});

describe('pagePlan', () => {
  it('covers every position once, in pages of at most size', () => {
    for (const [total, size, at] of [
      [2500, 1000, 0],
      [2500, 1000, 1700],
      [2500, 1000, 99999],
      [1000, 1000, 5],
      [1, 1000, 0],
      [7, 3, 4],
    ]) {
      const plan = pagePlan(total!, size!, at!);
      const seen = new Uint8Array(total!);
      for (const [f, t] of plan) {
        expect(t - f).toBeGreaterThan(0);
        expect(t - f).toBeLessThanOrEqual(size!);
        for (let i = f; i < t; i++) seen[i]!++;
      }
      expect([...seen].every((c) => c === 1)).toBe(true);
    }
  });
  it('puts the page holding the cursor first, then the later pages, then the earlier', () => {
    expect(pagePlan(2500, 1000, 1700)).toEqual([
      [1000, 2000],
      [2000, 2500],
      [0, 1000],
    ]);
    expect(pagePlan(2500, 1000, -4)[0]).toEqual([0, 1000]);
    expect(pagePlan(2500, 1000, 1e9)[0]).toEqual([2000, 2500]);
    expect(pagePlan(0, 1000)).toEqual([]);
    expect(RUN_PAGE).toBeLessThanOrEqual(1000);
  });
});

describe('run frame pages', () => {
  const rec = (index: number, state = 'STATE_TRACK') => ({ index, state, teats: [{ tipMm: { x: 1, y: 2, z: 3 }, tracked: true }] });
  const truth = { teats: [{ name: 'FL', tipMm: { x: 1, y: 2, z: 4 }, visible: true }] };
  it('decodes the route envelope with truth', () => {
    const p = decodeRunFramesPage({ run: 'r1', from: 10, to: 12, total: 40, frames: [rec(110), rec(111, 'STATE_LOST')], truth: [truth, null] }, 10);
    expect(p.from).toBe(10);
    expect(p.to).toBe(12);
    expect(p.total).toBe(40);
    expect(p.hasTruth).toBe(true);
    expect(p.items.map((i) => i.frame.index)).toEqual([110, 111]);
    expect(p.items[1]!.frame.state).toBe('LOST');
    expect(p.items[0]!.truth?.teats[0]?.tipMm).toEqual([1, 2, 4]);
    expect(p.items[1]!.truth).toBeNull();
  });
  it('knows a run without truth', () => {
    const p = decodeRunFramesPage({ from: 0, to: 1, total: 1, frames: [rec(0)], truth: null }, 0);
    expect(p.hasTruth).toBe(false);
    expect(p.items[0]!.truth).toBeNull();
  });
  it('merges pages into the store by video frame index, in any order', () => {
    const store = new FrameStore(50);
    const page = (from: number, n: number) =>
      decodeRunFramesPage({ from, to: from + n, total: 30, frames: Array.from({ length: n }, (_, k) => rec(20 + from + k)), truth: null }, from);
    expect(store.putMany(page(20, 10).items)).toBe(10);
    expect(store.putMany(page(0, 20).items)).toBe(20);
    expect(store.knownCount).toBe(30);
    expect(store.firstGap()).toBe(0);
    expect(store.firstGap(20)).toBe(50);
    expect(store.records[20]?.index).toBe(20);
    expect(store.records[49]?.index).toBe(49);
    // The same page again adds nothing new.
    store.putMany(page(0, 20).items);
    expect(store.knownCount).toBe(30);
  });
});

describe('local player', () => {
  const s0 = { playing: false, frame: 5, speed: 1 };
  it('seeks and steps within the video', () => {
    expect(applyOp(s0, { op: 'seek', frame: 12.4 }, 20).frame).toBe(12);
    expect(applyOp(s0, { op: 'seek', frame: 99 }, 20).frame).toBe(19);
    expect(applyOp(s0, { op: 'seek', frame: -3 }, 20).frame).toBe(0);
    expect(applyOp(s0, { op: 'step', delta: 1 }, 20).frame).toBe(6);
    expect(applyOp(s0, { op: 'step', delta: -10 }, 20).frame).toBe(0);
    expect(applyOp({ ...s0, playing: true }, { op: 'step', delta: 1 }, 20).playing).toBe(false);
  });
  it('plays, pauses, restarts from the end and clamps the speed', () => {
    expect(applyOp(s0, { op: 'play' }, 20)).toMatchObject({ playing: true, frame: 5 });
    expect(applyOp({ ...s0, frame: 19 }, { op: 'play' }, 20)).toMatchObject({ playing: true, frame: 0 });
    expect(applyOp({ ...s0, playing: true }, { op: 'pause' }, 20).playing).toBe(false);
    expect(applyOp(s0, { op: 'speed', value: 4 }, 20).speed).toBe(4);
    expect(applyOp(s0, { op: 'speed', value: 1000 }, 20).speed).toBe(16);
    expect(applyOp(s0, { op: 'speed', value: -1 }, 20).speed).toBe(1);
  });
  it('advances at fps × speed', () => {
    expect(playFrame(10, 1000, 30, 1)).toBe(40);
    expect(playFrame(10, 500, 30, 2)).toBe(40);
    expect(playFrame(0, 99, 10, 1)).toBe(0);
    expect(playFrame(0, 1000, 0, 1)).toBe(30);
  });
});
