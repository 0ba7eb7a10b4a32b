import { describe, expect, it } from 'vitest';
import { parseCompare, wireNumber } from '../api/runs';
import type { RunRow } from '../api/runsTypes';
import { NAN_COLOR, colorScale, rampColor } from './colorScale';
import { laneScales } from './compareView';
import { brushHits, fitPoints, inPolygon, inRect, nearest, normRect, overlapGroups } from './geometry';
import { bestIndex, formatMetric, formatNumber, formatParam, metricValue, paramValue, varyingParams } from './metrics';
import { axisDomain, axisX, passesBrushes, valueAt, yOf } from './parcoordsScale';
import { isRunsHash, parsePcFilters, parseRunsHash, runsHash } from './route';
import { sortRows } from './runsTable';
import { MAX_COMPARE, clickSelect, pickCompare, rangeIds } from './selection';
import { sweepBody } from './sweepLauncher';

function run(id: string, video: string, p: Record<string, number>, summary: Partial<RunRow['summary']> = {}): RunRow {
  return {
    id,
    video,
    sweep: 's1',
    param_names: Object.keys(p),
    params: Object.values(p),
    summary: { frames: 100, track_share: 0.5, lost_episodes: 0, accuracy: null, ...summary },
  };
}

describe('colour scale', () => {
  it('spans the finite values and greys NaN', () => {
    const s = colorScale([0.2, NaN, 0.8, Infinity, 0.5]);
    expect(s.lo).toBe(0.2);
    expect(s.hi).toBe(0.8);
    expect(s.t(0.5)).toBeCloseTo(0.5);
    expect(s.t(-1)).toBe(0);
    expect(s.t(9)).toBe(1);
    expect(s.color(NaN)).toBe(NAN_COLOR);
    expect(s.color(0.2)).toBe('rgb(68, 1, 84)'); // viridis start
    expect(s.color(0.8)).toBe('rgb(253, 231, 37)'); // viridis end
  });
  it('reverses the ramp when lower is better (bright = good)', () => {
    const s = colorScale([1, 10], { reversed: true });
    expect(s.color(1)).toBe('rgb(253, 231, 37)');
    expect(s.color(10)).toBe('rgb(68, 1, 84)');
  });
  it('puts a constant or empty metric mid-ramp', () => {
    expect(colorScale([3, 3]).t(3)).toBe(0.5);
    const e = colorScale([NaN]);
    expect([e.lo, e.hi]).toEqual([0, 1]);
  });
  it('interpolates between stops', () => {
    expect(rampColor(['#000000', '#ffffff'], 0.5)).toBe('rgb(128, 128, 128)');
    expect(rampColor(['#000000', '#ff0000', '#ffffff'], 0.25)).toBe('rgb(128, 0, 0)');
  });
});

describe('scatter geometry and brushes', () => {
  it('fits with one scale for both axes, y up, and inverts', () => {
    const f = fitPoints(
      [
        [0, 0],
        [10, 5],
      ],
      220,
      220,
      10,
    );
    expect(f.scale).toBeCloseTo(20);
    const a = f.toPx(0, 0);
    const b = f.toPx(10, 5);
    expect(b.x - a.x).toBeCloseTo(200);
    expect(a.y - b.y).toBeCloseTo(100); // higher data y is higher up (smaller px y)
    expect(a.y).toBeCloseTo(160); // centred vertically: (200 − 100) / 2 + 10 + 100
    const back = f.toData(b.x, b.y);
    expect(back.x).toBeCloseTo(10);
    expect(back.y).toBeCloseTo(5);
  });
  it('ignores non-finite points and survives a single point', () => {
    const f = fitPoints(
      [
        [1, 1],
        [NaN, 3],
      ],
      100,
      100,
    );
    const p = f.toPx(1, 1);
    expect(Number.isFinite(p.x) && Number.isFinite(p.y)).toBe(true);
  });
  it('hit-tests rectangles (either drag direction) and lassos (concave)', () => {
    const pts = [
      { x: 1, y: 1 },
      { x: 5, y: 5 },
      { x: 9, y: 1 },
      { x: 5, y: 2 },
      { x: NaN, y: 1 },
    ];
    expect(brushHits(pts, { rect: normRect({ x: 6, y: 6 }, { x: 0, y: 0 }) })).toEqual([0, 1, 3]);
    expect(inRect({ x: 6, y: 6 }, normRect({ x: 0, y: 0 }, { x: 6, y: 6 }))).toBe(true);
    // A "V": the notch at (5, 2) is outside.
    const lasso = [
      { x: 0, y: 0 },
      { x: 5, y: 4 },
      { x: 10, y: 0 },
      { x: 10, y: 6 },
      { x: 0, y: 6 },
    ];
    expect(inPolygon({ x: 5, y: 2 }, lasso)).toBe(false);
    expect(inPolygon({ x: 5, y: 5 }, lasso)).toBe(true);
    expect(brushHits(pts, { lasso })).toEqual([0, 1, 2]);
    expect(inPolygon({ x: 1, y: 1 }, [{ x: 0, y: 0 }, { x: 2, y: 2 }])).toBe(false);
  });
  it('finds the nearest point within a radius', () => {
    const pts = [
      { x: 0, y: 0 },
      { x: 10, y: 0 },
    ];
    expect(nearest(pts, { x: 8, y: 1 }, 5)).toBe(1);
    expect(nearest(pts, { x: 5, y: 20 }, 5)).toBe(-1);
  });
});

describe('parallel coordinates scaling', () => {
  it('maps values between bottom (lo) and top (hi), NaN to the missing band', () => {
    const ax = { lo: 0, hi: 10 };
    expect(yOf(0, ax, 20, 220)).toBe(220);
    expect(yOf(10, ax, 20, 220)).toBe(20);
    expect(yOf(5, ax, 20, 220)).toBe(120);
    expect(yOf(99, ax, 20, 220)).toBe(20);
    expect(yOf(NaN, ax, 20, 220, 240)).toBe(240);
    expect(valueAt(120, ax, 20, 220)).toBeCloseTo(5);
    expect(valueAt(0, ax, 20, 220)).toBe(10);
  });
  it('widens constant domains and ignores non-finite values', () => {
    expect(axisDomain([2, NaN, 2])).toEqual([1, 3]);
    expect(axisDomain([0, 0])).toEqual([-0.5, 0.5]);
    expect(axisDomain([NaN])).toEqual([0, 1]);
    expect(axisDomain([3, -1, Infinity])).toEqual([-1, 3]);
  });
  it('spaces axes and applies brushes', () => {
    expect(axisX(0, 3, 200, 20)).toBe(20);
    expect(axisX(2, 3, 200, 20)).toBe(180);
    expect(axisX(0, 1, 200, 20)).toBe(100);
    const v = new Map([
      ['a', 1],
      ['b', NaN],
    ]);
    expect(passesBrushes(v, new Map())).toBe(true);
    expect(passesBrushes(v, new Map([['a', [2, 0] as [number, number]]]))).toBe(true);
    expect(passesBrushes(v, new Map([['a', [2, 3] as [number, number]]]))).toBe(false);
    expect(passesBrushes(v, new Map([['b', [0, 9] as [number, number]]]))).toBe(false);
  });
});

describe('selection', () => {
  const order = ['r1', 'r2', 'r3', 'r4', 'r5'];
  it('selects ranges from the anchor in either direction', () => {
    expect(rangeIds(order, 'r2', 'r4')).toEqual(['r2', 'r3', 'r4']);
    expect(rangeIds(order, 'r4', 'r2')).toEqual(['r2', 'r3', 'r4']);
    expect(rangeIds(order, null, 'r3')).toEqual(['r3']);
    expect(rangeIds(order, 'gone', 'r3')).toEqual(['r3']);
  });
  it('replaces, toggles and adds ranges', () => {
    expect(clickSelect(['r1'], order, 'r1', 'r3', 'replace')).toEqual(['r3']);
    expect(clickSelect(['r1'], order, 'r1', 'r3', 'toggle')).toEqual(['r1', 'r3']);
    expect(clickSelect(['r1', 'r3'], order, 'r1', 'r3', 'toggle')).toEqual(['r1']);
    expect(clickSelect(['r1'], order, 'r2', 'r4', 'range')).toEqual(['r1', 'r2', 'r3', 'r4']);
  });
  it('compares the runs of the most selected video, best first, at most 8 spread over the metric', () => {
    const rows = new Map<string, RunRow>();
    for (let i = 0; i < 20; i++) rows.set(`a${i}`, run(`a${i}`, 'v1', { x: i }, { track_share: i / 19 }));
    rows.set('b0', run('b0', 'v2', { x: 0 }));
    const pick = pickCompare(['b0', ...Array.from({ length: 20 }, (_, i) => `a${i}`)], rows, 'track_share');
    expect(pick.video).toBe('v1');
    expect(pick.ofVideo).toBe(20);
    expect(pick.selected).toBe(21);
    expect(pick.ids.length).toBe(MAX_COMPARE);
    expect(pick.ids[0]).toBe('a19');
    expect(pick.ids.at(-1)).toBe('a0');
    // lower is better for the error: the best (smallest) first, NaN last
    rows.set('e1', run('e1', 'v3', {}, { accuracy: { median_error_mm: 5 } }));
    rows.set('e2', run('e2', 'v3', {}, { accuracy: { median_error_mm: 2 } }));
    rows.set('e3', run('e3', 'v3', {}, { accuracy: null }));
    expect(pickCompare(['e1', 'e3', 'e2'], rows, 'accuracy.median_error_mm').ids).toEqual(['e2', 'e1', 'e3']);
  });
  it('needs two runs of one video', () => {
    const rows = new Map<string, RunRow>([
      ['a', run('a', 'v1', {})],
      ['b', run('b', 'v2', {})],
    ]);
    expect(pickCompare(['a', 'b'], rows, 'track_share').ids).toEqual([]);
    expect(pickCompare([], rows, 'track_share').ids).toEqual([]);
  });
});

describe('route', () => {
  it('recognises and round-trips #runs hashes', () => {
    expect(isRunsHash('#runs')).toBe(true);
    expect(isRunsHash('#runs?sweep=s1')).toBe(true);
    expect(isRunsHash('#runsx')).toBe(false);
    expect(isRunsHash('#tracker')).toBe(false);
    const h = runsHash({ sweep: 's2', sel: ['r1', 'r7'], metric: 'accuracy.median_error_mm', method: 'tsne', frame: 12 });
    expect(h).toBe('#runs?sweep=s2&sel=r1,r7&metric=accuracy.median_error_mm&method=tsne&frame=12');
    expect(parseRunsHash(h)).toEqual({ sweep: 's2', sel: ['r1', 'r7'], metric: 'accuracy.median_error_mm', method: 'tsne', frame: 12, perp: null, pc: [] });
    expect(parseRunsHash('#runs')).toEqual({ sweep: null, sel: [], metric: null, method: null, frame: null, perp: null, pc: [] });
  });

  it('keeps the perplexity and the parallel-coordinate filters (keys may hold colons)', () => {
    const pc: [string, [number, number]][] = [
      ['param:ncc_min', [0.25, 0.5]],
      ['metric:accuracy.median_error_mm', [1, 3.5]],
    ];
    const h = runsHash({ sweep: 's1', method: 'tsne', perp: 5, pc });
    expect(h).toBe('#runs?sweep=s1&method=tsne&perp=5&pc=param:ncc_min:0.25:0.5;metric:accuracy.median_error_mm:1:3.5');
    const r = parseRunsHash(h);
    expect(r.perp).toBe(5);
    expect(r.pc).toEqual(pc);
    expect(parsePcFilters('x:1;:1:2;k:3:1;k:a:2')).toEqual([]);
    expect(runsHash({})).toBe('#runs');
  });
});

describe('metrics', () => {
  const r = run('r1', 'v1', { ncc_min: 0.35, r_max_mm: 17 }, { track_share: 0.75, accuracy: { median_error_mm: 2.25, frames_all_within: null } });
  it('reads dotted figures and parameters, NaN when missing', () => {
    expect(metricValue(r, 'track_share')).toBe(0.75);
    expect(metricValue(r, 'metric:accuracy.median_error_mm')).toBe(2.25);
    expect(metricValue(r, 'accuracy.frames_all_within')).toBeNaN();
    expect(metricValue(run('x', 'v', {}), 'accuracy.median_error_mm')).toBeNaN();
    expect(paramValue(r, 'param:r_max_mm')).toBe(17);
    expect(paramValue(r, 'nope')).toBeNaN();
  });
  it('lists the parameters that vary', () => {
    const rows = [run('a', 'v', { p: 1, q: 2, z: 0 }), run('b', 'v', { p: 1, q: 3, z: 0 }), run('c', 'v', { p: 1, q: 2, z: 0 })];
    expect(varyingParams(rows)).toEqual(['q']);
    expect(varyingParams([])).toEqual([]);
  });
  it('formats with units', () => {
    expect(formatMetric('track_share', 0.994)).toBe('99.4 %');
    expect(formatMetric('track_share', 1)).toBe('100 %');
    expect(formatMetric('accuracy.median_error_mm', 1.8379)).toBe('1.84 mm');
    expect(formatMetric('tracker_fps', 699.8)).toBe('700 fps');
    expect(formatMetric('lost_episodes', 3)).toBe('3');
    expect(formatMetric('track_share', NaN)).toBe('–');
    expect(formatNumber(Infinity)).toBe('∞');
    expect(formatNumber(4000)).toBe('4,000');
    expect(formatNumber(0.35)).toBe('0.35');
    expect(formatParam(22, 'mm')).toBe('22 mm');
    expect(formatParam(NaN, 'mm')).toBe('–');
  });
  it('finds the best value by direction, skipping NaN', () => {
    expect(bestIndex([0.5, NaN, 0.9, 0.9], 'high')).toBe(2);
    expect(bestIndex([3, 1, NaN], 'low')).toBe(1);
    expect(bestIndex([NaN], 'low')).toBe(-1);
  });
  it('sorts table rows with NaN last in both directions', () => {
    const rows = [run('r10', 'v', {}, { track_share: 0.2 }), run('r2', 'v', {}, { track_share: NaN }), run('r3', 'v', {}, { track_share: 0.9 })];
    const col = { key: 'track_share', label: '', kind: 'metric' as const };
    expect(sortRows(rows, col, 1).map((x) => x.id)).toEqual(['r10', 'r3', 'r2']);
    expect(sortRows(rows, col, -1).map((x) => x.id)).toEqual(['r3', 'r10', 'r2']);
    expect(sortRows(rows, { key: 'id', label: '', kind: 'id' }, 1).map((x) => x.id)).toEqual(['r2', 'r3', 'r10']);
  });
});

describe('compare parsing', () => {
  const body = {
    video: 'v1',
    first_frame: 10,
    frames: 4,
    state_names: ['SEARCH', 'TRACK', 'LOST'],
    runs: [
      { id: 'r3', sweep: 's1', origin: 'sweep', summary: { frames: 4, track_share: 0.5, lost_episodes: 1, accuracy: null } },
      { id: 'r7', sweep: null, origin: 'track' },
    ],
    series: [
      {
        id: 'r3',
        state: [0, 1, 1, 2],
        matches: [0, 4, 5, 1],
        verified: [0, 4, 4, 0],
        teats_matched: [0, 4, 4, 0],
        model_cost: [null, 1.5, 2, null],
        shape_cost: [0, 1, 1, 0],
        max_error_mm: [null, 1.2, 'Infinity', 3],
        teat_error_mm: [[null, null, null, null], [1, 1.2, 0.5, null], [1, 'Infinity', 2, 2], [3, 1, 1, 1]],
      },
      { id: 'r7', state: [1, 1], matches: [4, 4], max_error_mm: [2, 2] },
    ],
    params: [
      { name: 'ncc_min', values: [0.35, 0.5], differs: true },
      { name: 'n_lost', values: [4, 4], differs: false },
    ],
    results: [
      { name: 'track_share', values: [0.5, 1] },
      { name: 'accuracy.median_error_mm', values: [2, null] },
    ],
    disagreements: [
      { frame: 12, score_mm: 48.2, states: [1, 2], worst_teat: 1 },
      { frame: 11, score_mm: 3.5, states: [1, 1], teats: [[1, 2], null] },
      { frame: 13, score_mm: 2, states: [1, 1], worst_teat: 'RL' },
    ],
  };
  it('turns wire numbers into NaN / Infinity', () => {
    expect(wireNumber(null)).toBeNaN();
    expect(wireNumber('Infinity')).toBe(Infinity);
    expect(wireNumber(2.5)).toBe(2.5);
    expect(wireNumber('x')).toBeNaN();
  });
  it('parses series, states, tables and disagreements', () => {
    const c = parseCompare(body);
    expect(c.video).toBe('v1');
    expect(c.firstFrame).toBe(10);
    expect(c.frames).toBe(4);
    expect(c.runs.map((r) => r.id)).toEqual(['r3', 'r7']);
    const [a, b] = c.series;
    expect(a!.state).toEqual(['SEARCH', 'TRACK', 'TRACK', 'LOST']);
    expect([...a!.maxErrorMm]).toEqual([NaN, 1.2, Infinity, 3]);
    expect([...a!.modelCost]).toEqual([NaN, 1.5, 2, NaN]);
    expect(a!.teatErrorMm.length).toBe(4);
    expect(a!.teatErrorMm[1]![2]).toBe(Infinity);
    expect(a!.teatErrorMm[3]![1]).toBeNaN();
    // a short series is padded to the shared frame count
    expect(b!.state).toEqual(['TRACK', 'TRACK', null, null]);
    expect([...b!.matches]).toEqual([4, 4, NaN, NaN]);
    expect(b!.teatErrorMm).toEqual([]);
    expect(c.params[0]).toEqual({ name: 'ncc_min', values: [0.35, 0.5], differs: true });
    expect(c.params[1]!.differs).toBe(false);
    expect(c.results[0]!.differs).toBe(true); // computed when the server leaves it out
    expect(c.results[1]!.values[1]).toBeNaN();
    expect(c.disagreements[0]).toEqual({ frame: 12, scoreMm: 48.2, states: ['TRACK', 'LOST'], worstTeat: 1 });
    expect(c.disagreements[1]!.worstTeat).toBeNull();
    expect(c.disagreements[2]!.worstTeat).toBe(2); // by name
  });
  it('survives an empty or odd body', () => {
    const c = parseCompare({});
    expect(c.frames).toBe(0);
    expect(c.series).toEqual([]);
    expect(parseCompare(null).disagreements).toEqual([]);
  });
  it('derives shared lane scales', () => {
    const c = parseCompare(body);
    const s = laneScales(c.series);
    expect(s.errMax).toBe(10); // small errors: at least 10 mm
    expect(s.matchMax).toBe(5);
    expect(s.costMax).toBeCloseTo(2.2);
  });
});

describe('sweep launcher body', () => {
  it('builds a random or grid sweep and names the field at fault', () => {
    expect(sweepBody(['v1', 'v2'], 'random', 100, 5, 7, [{ param: 'ncc_min', min: 0.1, max: 0.8 }])).toEqual({
      videos: ['v1', 'v2'],
      sweep: { mode: 'random', seed: 7, samples: 100, axes: [{ param: 'ncc_min', min: 0.1, max: 0.8 }] },
    });
    expect(sweepBody(['v1'], 'grid', 0, 3, 1, [{ param: 'n_lost', min: 2, max: 6 }]).sweep).toEqual({
      mode: 'grid',
      seed: 1,
      axes: [{ param: 'n_lost', min: 2, max: 6, steps: 3 }],
    });
    expect(() => sweepBody([], 'random', 10, 5, 1, [{ param: 'a', min: 0, max: 1 }])).toThrow(/videos/);
    expect(() => sweepBody(['v'], 'random', 10, 5, 1, [])).toThrow(/axes/);
    expect(() => sweepBody(['v'], 'random', 10, 5, 1, [{ param: 'a', min: 2, max: 1 }])).toThrow(/^a:/);
    expect(() => sweepBody(['v'], 'random', 1.5, 5, 1, [{ param: 'a', min: 0, max: 1 }])).toThrow(/samples/);
    expect(() => sweepBody(['v'], 'grid', 1, 1, 1, [{ param: 'a', min: 0, max: 1 }])).toThrow(/steps/);
    expect(() =>
      sweepBody(['v'], 'random', 3, 5, 1, [
        { param: 'a', min: 0, max: 1 },
        { param: 'a', min: 0, max: 1 },
      ]),
    ).toThrow(/twice/);
  });
});

describe('overlapGroups', () => {
  it('groups points within the tolerance of a group head, as brute force does', () => {
    const pts = [
      { x: 10, y: 10 },
      { x: 10.4, y: 10.2 },
      { x: 50, y: 50 },
      { x: 10, y: 10 },
      { x: 50, y: 52 },
      { x: NaN, y: 1 },
      { x: 0.2, y: 0 },
      { x: -0.3, y: 0.1 },
    ];
    // Brute force: each point joins the first earlier head within 1 px, else heads its own group.
    const heads: number[][] = [];
    pts.forEach((p, i) => {
      if (!Number.isFinite(p.x)) return;
      const g = heads.find((h) => Math.hypot(pts[h[0]!]!.x - p.x, pts[h[0]!]!.y - p.y) <= 1);
      if (g) g.push(i);
      else heads.push([i]);
    });
    expect(overlapGroups(pts, 1)).toEqual(heads.filter((g) => g.length > 1));
    expect(overlapGroups(pts, 1)).toEqual([
      [0, 1, 3],
      [6, 7],
    ]);
  });
});
