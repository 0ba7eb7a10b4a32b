import { describe, expect, it } from 'vitest';
import { decodeFrameRecord } from '../api/trackerLog';
import { frameAt, frameLeft, tickStep, xOfFrame } from './frameAxis';
import { FrameStore } from './frameStore';
import { isTrackerHash, trackerHash, trackerHashParams } from './route';
import { extent, teatSeries } from './series';
import { paramProblem } from './setupPanel';
import { MISSING, hasModel, teatValues } from './frameData';

describe('frameAxis', () => {
  it('maps x to the frame covering it and back', () => {
    expect(frameAt(0, 500, 1000)).toBe(0);
    expect(frameAt(250, 500, 1000)).toBe(500);
    expect(frameAt(499.9, 500, 1000)).toBe(999);
    expect(frameAt(-5, 500, 1000)).toBe(0);
    expect(frameAt(600, 500, 1000)).toBe(999);
    for (const i of [0, 1, 137, 999]) expect(frameAt(xOfFrame(i, 500, 1000), 500, 1000)).toBe(i);
    for (const i of [0, 3, 9]) expect(frameAt(xOfFrame(i, 900, 10), 900, 10)).toBe(i);
    expect(frameLeft(5, 100, 10)).toBe(50);
    expect(frameAt(10, 0, 10)).toBe(0);
  });
  it('picks 1-2-5 tick steps', () => {
    expect(tickStep(1000, 10)).toBe(100);
    expect(tickStep(1000, 8)).toBe(200);
    expect(tickStep(30, 10)).toBe(5);
    expect(tickStep(3, 10)).toBe(1);
  });
});

const rec = (index: number, state: string, tip?: number[]) =>
  decodeFrameRecord({ index, state, teats: [tip ? { tipMm: tip, tracked: true, visible: true } : {}, {}, {}, {}] });

describe('FrameStore', () => {
  it('counts states, ignores out-of-range frames and notifies once per batch', () => {
    const s = new FrameStore(5);
    let calls = 0;
    s.subscribe(() => calls++);
    expect(s.put(0, rec(0, 'STATE_TRACK'))).toBe(true);
    expect(s.put(7, rec(7, 'STATE_TRACK'))).toBe(false);
    s.putMany([1, 2, 3].map((i) => ({ frame: rec(i, i === 2 ? 'STATE_LOST' : 'STATE_SEARCH'), truth: null })));
    expect(calls).toBe(2);
    expect(s.knownCount).toBe(4);
    expect(s.complete).toBe(false);
    expect(s.firstGap()).toBe(4);
    expect(s.stateCounts()).toEqual({ SEARCH: 2, TRACK: 1, LOST: 1 });
    s.put(4, rec(4, 'STATE_TRACK'));
    expect(s.complete).toBe(true);
    s.put(4, rec(4, 'STATE_LOST'));
    expect(s.knownCount).toBe(5);
    expect(s.stateCounts().LOST).toBe(2);
  });
  it('keeps known truth when a record comes without it', () => {
    const s = new FrameStore(2);
    const truth = { teats: [{ name: 'FL', tipMm: [0, 0, 0] as [number, number, number], tipPx: null, visible: true, boxPx: null, visibleFraction: 1, cupAttached: false }] };
    s.put(0, rec(0, 'STATE_TRACK'), truth);
    s.put(0, rec(0, 'STATE_TRACK'), null);
    expect(s.truth[0]).toBe(truth);
  });
});

describe('teatSeries', () => {
  it('gives estimate, truth and error per frame', () => {
    const s = new FrameStore(3);
    const truth = (z: number, visible = true) => ({
      teats: [{ name: 'FL', tipMm: [0, 0, z] as [number, number, number], tipPx: null, visible, boxPx: null, visibleFraction: 1, cupAttached: false }],
    });
    s.put(0, rec(0, 'STATE_TRACK', [3, 4, 500]), truth(500));
    s.put(1, rec(1, 'STATE_LOST'), truth(501));
    s.put(2, rec(2, 'STATE_TRACK', [0, 0, 510]), truth(500, false));
    const t = teatSeries(s, 0);
    expect([...t.estimate[2]]).toEqual([500, NaN, 510]);
    expect([...t.truth[2]]).toEqual([500, 501, 500]);
    expect(t.error[0]).toBe(5);
    expect(t.error[1]).toBeNaN();
    expect(t.error[2]).toBeNaN(); // truth not visible
    expect(extent([t.estimate[2], t.truth[2]])).toEqual([499.5, 510.5]);
    expect(extent([new Float64Array([NaN])])).toEqual([0, 1]);
  });
});

describe('route', () => {
  it('tells the tracker hash from the map hash and reads its parameters', () => {
    expect(isTrackerHash('#tracker')).toBe(true);
    expect(isTrackerHash('#tracker?replay=r1')).toBe(true);
    expect(isTrackerHash('#dataset=europe&value=count')).toBe(false);
    expect(isTrackerHash('#trackerx')).toBe(false);
    expect(isTrackerHash('')).toBe(false);
    expect(trackerHashParams('#tracker?replay=replay-3&video=v').get('replay')).toBe('replay-3');
    expect(trackerHashParams('#tracker').get('replay')).toBeNull();
    expect(trackerHashParams('#dataset=x').get('dataset')).toBeNull();
    expect(trackerHash('a b')).toBe('#tracker?replay=a%20b');
    expect(trackerHash('r', 42)).toBe('#tracker?replay=r&frame=42');
    expect(trackerHashParams(trackerHash('a b&c')).get('replay')).toBe('a b&c');
  });
});

describe('paramProblem', () => {
  const p = { name: 'n_lost', unit: '', default_value: 4, min: 1, max: 1000, integer: true, help: '' };
  it('checks numbers, whole numbers and the range; blank keeps the default', () => {
    expect(paramProblem(p, '')).toBeNull();
    expect(paramProblem(p, '12')).toBeNull();
    expect(paramProblem(p, 'x')).toMatch(/number/);
    expect(paramProblem(p, '2.5')).toMatch(/whole/);
    expect(paramProblem(p, '0')).toMatch(/\[1, 1000\]/);
    expect(paramProblem({ ...p, integer: false, min: 0, max: 1 }, '0.55')).toBeNull();
  });
});

describe('frame data of a LOST frame', () => {
  it('shows "-" for what the frame does not have, values for what it has', () => {
    const lost = decodeFrameRecord({ index: 7, state: 'STATE_LOST', teats: [{}, {}, {}, {}] });
    expect(lost.state).toBe('LOST');
    expect(hasModel(lost)).toBe(false);
    expect(teatValues(lost.teats[0]!)).toEqual([MISSING, MISSING, MISSING, MISSING, MISSING]);
    const seen = rec(8, 'STATE_TRACK', [1.25, -2, 300]);
    expect(hasModel(seen)).toBe(true);
    expect(teatValues(seen.teats[0]!).slice(1, 4)).toEqual(['1.3', '-2.0', '300.0']);
  });
});
