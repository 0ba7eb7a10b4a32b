import { describe, expect, it } from 'vitest';
import { decodeFrameRecord, decodeRunFrames, decodeState, decodeTruth, distance3, toNumber } from './trackerLog';

describe('toNumber', () => {
  it('reads numbers and the protobuf JSON strings', () => {
    expect(toNumber(3.5)).toBe(3.5);
    expect(toNumber('12')).toBe(12);
    expect(toNumber('NaN')).toBeNaN();
    expect(toNumber('Infinity')).toBe(Infinity);
    expect(toNumber('-Infinity')).toBe(-Infinity);
    expect(toNumber('abc', 7)).toBe(7);
    expect(toNumber('', 7)).toBe(7);
    expect(toNumber(undefined, -1)).toBe(-1);
    expect(toNumber(null)).toBe(0);
  });
});

describe('decodeState', () => {
  it('accepts enum names with and without prefix, and numbers', () => {
    expect(decodeState('STATE_TRACK')).toBe('TRACK');
    expect(decodeState('STATE_LOST')).toBe('LOST');
    expect(decodeState('STATE_SEARCH')).toBe('SEARCH');
    expect(decodeState('track')).toBe('TRACK');
    expect(decodeState(3)).toBe('LOST');
    expect(decodeState(2)).toBe('TRACK');
    expect(decodeState(1)).toBe('SEARCH');
    expect(decodeState(undefined)).toBe('SEARCH'); // proto3 omits the first enum value
  });
});

describe('decodeFrameRecord', () => {
  const full = {
    index: 17,
    timestampS: 0.68,
    validPixels: 20000,
    flyingPixels: 31,
    matches: 9,
    verified: 4,
    candidates: [
      { u: 40.5, v: 60.25, ncc: 0.91, templateIndex: 2, verified: true, tipMm: [-80, 40, 500], axis: [0, -1, 0], radiusMm: 11, fitRmsMm: 1.2, points: 80, teat: 1 },
      { u: 10, v: 12, ncc: 0.6, teat: -1 },
      { u: 11, v: 13, ncc: 0.7, verified: true, tipMm: [1, 2, 3] },
    ],
    model: { pairMm: [100, 'NaN', 120, 130, 140, 150], pairErrorMm: [1, 'NaN', 2, 3, 4, 5], shapeCost: 3, nccCost: 0.1, cost: 5, teatsMatched: 3 },
    state: 'STATE_TRACK',
    teats: [
      { tipMm: [-80, 40, 500], tipPx: [40.5, 60.25], visible: true, tracked: true, confidence: 0.9, radiusMm: 11 },
      { tipMm: [80, 40, 500], tipPx: [120, 60], tracked: true, confidence: 0.4 },
      {},
      { tipMm: [80, 40, 600], tipPx: [120, 30], visible: true, tracked: true },
    ],
    times: { preprocessUs: 100, detectUs: 200, verifyUs: 50, modelUs: 10 },
  };

  it('decodes every field of a full record', () => {
    const f = decodeFrameRecord(full);
    expect(f.index).toBe(17);
    expect(f.timestampS).toBe(0.68);
    expect(f.matches).toBe(9);
    expect(f.verified).toBe(4);
    expect(f.state).toBe('TRACK');
    expect(f.candidates).toHaveLength(3);
    expect(f.candidates[0]).toMatchObject({ u: 40.5, v: 60.25, ncc: 0.91, templateIndex: 2, verified: true, radiusMm: 11, fitRmsMm: 1.2, points: 80, teat: 1 });
    expect(f.candidates[0]!.tipMm).toEqual([-80, 40, 500]);
    expect(f.candidates[1]!.teat).toBe(-1);
    expect(f.candidates[1]!.verified).toBe(false);
    expect(f.candidates[1]!.tipMm).toBeNull();
    expect(f.candidates[2]!.teat).toBe(0); // proto3 omits teat 0 (FL)
    expect(f.model.pairMm[1]).toBeNaN();
    expect(f.model.pairMm[5]).toBe(150);
    expect(f.model.cost).toBe(5);
    expect(f.model.teatsMatched).toBe(3);
    expect(f.teats).toHaveLength(4);
    expect(f.teats[0]).toEqual({ tipMm: [-80, 40, 500], tipPx: [40.5, 60.25], visible: true, tracked: true, confidence: 0.9, radiusMm: 11 });
    expect(f.teats[1]!.visible).toBe(false);
    expect(f.teats[2]).toEqual({ tipMm: null, tipPx: null, visible: false, tracked: false, confidence: 0, radiusMm: 0 });
    expect(f.times.totalUs).toBe(360);
  });

  it('fills omitted defaults (protobuf JSON drops 0, false, empty and the first enum value)', () => {
    const f = decodeFrameRecord({}, 5);
    expect(f.index).toBe(5);
    expect(f.state).toBe('SEARCH');
    expect(f.matches).toBe(0);
    expect(f.candidates).toEqual([]);
    expect(f.teats).toHaveLength(4);
    expect(f.model.pairMm).toHaveLength(6);
    expect(f.model.pairMm.every(Number.isNaN)).toBe(true);
    expect(decodeFrameRecord({ index: 0 }, 5).index).toBe(0);
  });

  it('accepts snake_case names, string int64 and {x,y,z} points', () => {
    const f = decodeFrameRecord({
      index: '42',
      timestamp_s: 1.5,
      valid_pixels: '123',
      state: 'LOST',
      teats: [{ tip_mm: { x: 1, y: 2, z: 3 }, tip_px: { u: 4, v: 5 }, visible: true }],
      times: { preprocess_us: '7', total_us: 99 },
    });
    expect(f.index).toBe(42);
    expect(f.timestampS).toBe(1.5);
    expect(f.validPixels).toBe(123);
    expect(f.state).toBe('LOST');
    expect(f.teats[0]!.tipMm).toEqual([1, 2, 3]);
    expect(f.teats[0]!.tipPx).toEqual([4, 5]);
    expect(f.times.preprocessUs).toBe(7);
    expect(f.times.totalUs).toBe(99);
  });

  it('never throws on junk', () => {
    for (const junk of [null, 3, 'x', [], { teats: 'no', candidates: {}, model: [] }]) {
      expect(() => decodeFrameRecord(junk)).not.toThrow();
    }
  });
});

describe('decodeTruth', () => {
  it('decodes the manifest truth (snake_case) and orders the teats by name', () => {
    const t = decodeTruth({
      teats: [
        { name: 'FR', tip_mm: [1, 2, 3], tip_px: [4, 5], visible: true, visible_fraction: 0.5, box_px: [1, 2, 3, 4], cup_attached: false },
        { name: 'FL', tip_mm: [0, 0, 0], tip_px: null, visible: false, box_px: null, cup_attached: true },
        { name: 'RR', tip_mm: [9, 9, 9] },
        { name: 'RL', tip_mm: [8, 8, 8] },
      ],
    });
    expect(t!.teats.map((x) => x.name)).toEqual(['FL', 'FR', 'RL', 'RR']);
    expect(t!.teats[0]).toMatchObject({ tipPx: null, boxPx: null, cupAttached: true, visible: false });
    expect(t!.teats[1]).toMatchObject({ tipMm: [1, 2, 3], tipPx: [4, 5], boxPx: [1, 2, 3, 4], visible: true, visibleFraction: 0.5 });
  });

  it('unwraps the log FrameTruthEntry and reads a {x, y, w, h} box', () => {
    const t = decodeTruth({ hasTruth: true, value: { teats: [{ tipMm: [1, 2, 3], tipPx: [], boxPx: { x: 2.5, y: 3.5, w: 1, h: 2 } }, {}, {}, {}] } });
    expect(t!.teats.map((x) => x.name)).toEqual(['FL', 'FR', 'RL', 'RR']);
    expect(t!.teats[0]).toMatchObject({ tipMm: [1, 2, 3], tipPx: null, boxPx: [2.5, 3.5, 1, 2] });
    expect(decodeTruth({ hasTruth: false })).toBeNull();
  });

  it('is null without truth', () => {
    expect(decodeTruth(null)).toBeNull();
    expect(decodeTruth({})).toBeNull();
    expect(decodeTruth({ teats: [] })).toBeNull();
  });
});

describe('decodeRunFrames', () => {
  it('accepts a bare array, {frames}, {frame, truth} items and a parallel truth array', () => {
    expect(decodeRunFrames([{ index: 3 }, {}], 3).map((x) => x.frame.index)).toEqual([3, 4]);
    const wrapped = decodeRunFrames({ frames: [{ frame: { state: 'STATE_LOST' }, index: 8, truth: { teats: [{ name: 'FL', tipMm: [1, 1, 1] }] } }] }, 8);
    expect(wrapped[0]!.frame.index).toBe(8);
    expect(wrapped[0]!.frame.state).toBe('LOST');
    expect(wrapped[0]!.truth!.teats[0]!.tipMm).toEqual([1, 1, 1]);
    const parallel = decodeRunFrames({ frames: [{ index: 0 }, { index: 1 }], truth: [null, { teats: [{ name: 'RR' }] }] });
    expect(parallel[0]!.truth).toBeNull();
    expect(parallel[1]!.truth!.teats[0]!.name).toBe('RR');
    expect(decodeRunFrames({ nothing: true })).toEqual([]);
  });
});

describe('distance3', () => {
  it('is Euclidean, NaN when a point is missing', () => {
    expect(distance3([0, 0, 0], [3, 4, 12])).toBe(13);
    expect(distance3(null, [1, 1, 1])).toBeNaN();
  });
});
