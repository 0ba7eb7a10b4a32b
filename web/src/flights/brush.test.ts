import { describe, expect, it } from 'vitest';
import {
  binInWindow,
  brushDomain,
  coversDomain,
  hitTest,
  moveWindow,
  resizeWindow,
  snapToGrid,
  timeToX,
  windowFromDrag,
  xToTime,
  SECOND_GRID,
  MIN_VIEW_SECONDS,
  zoomView,
  clampView,
  nudgeStep,
  parseIsoUtc,
  formatIsoUtc,
} from './brush';

// One day in 15-minute bins, as the server answers for 2018-01-01.
const T0 = 1514764800;
const grid = { origin: T0, step: 900 };
const hist = { t0: T0, bin_seconds: 900, counts: new Array<number>(96).fill(1) };
const domain = brushDomain(T0 + 10, T0 + 86390, hist);

describe('domain and pixels', () => {
  it('widens the data range to whole bins', () => {
    expect(domain).toEqual({ start: T0, end: T0 + 86400 });
    expect(brushDomain(100, 199)).toEqual({ start: 100, end: 200 });
  });

  it('maps time to pixels and back, clamping outside the plot', () => {
    expect(timeToX(T0 + 43200, domain, 960)).toBe(480);
    expect(xToTime(480, domain, 960)).toBe(T0 + 43200);
    expect(xToTime(-5, domain, 960)).toBe(T0);
    expect(xToTime(2000, domain, 960)).toBe(T0 + 86400);
  });
});

describe('snapping', () => {
  it('snaps to bin edges', () => {
    expect(snapToGrid(T0 + 1000, grid)).toBe(T0 + 900);
    expect(snapToGrid(T0 + 1000, grid, 'floor')).toBe(T0 + 900);
    expect(snapToGrid(T0 + 1000, grid, 'ceil')).toBe(T0 + 1800);
    // An edge is its own floor and ceil.
    expect(snapToGrid(T0 + 1800, grid, 'ceil')).toBe(T0 + 1800);
    expect(snapToGrid(T0 + 1800, grid, 'floor')).toBe(T0 + 1800);
  });
});

describe('windowFromDrag', () => {
  it('orders the ends and widens to whole bins', () => {
    expect(windowFromDrag(T0 + 5000, T0 + 1000, domain, grid)).toEqual({ start: T0 + 900, end: T0 + 5400 });
  });

  it('is at least one bin wide, also at the domain end', () => {
    expect(windowFromDrag(T0 + 1800, T0 + 1800, domain, grid)).toEqual({ start: T0 + 1800, end: T0 + 2700 });
    const end = T0 + 86400;
    expect(windowFromDrag(end, end, domain, grid)).toEqual({ start: end - 900, end });
  });

  it('clamps to the domain', () => {
    expect(windowFromDrag(T0 - 5000, T0 + 90000, domain, grid)).toEqual(domain);
  });
});

describe('move and resize', () => {
  const w = { start: T0 + 3600, end: T0 + 7200 };

  it('moves by whole bins and keeps the width inside the domain', () => {
    expect(moveWindow(w, 1000, domain, grid)).toEqual({ start: T0 + 4500, end: T0 + 8100 });
    expect(moveWindow(w, -1e6, domain, grid)).toEqual({ start: T0, end: T0 + 3600 });
    expect(moveWindow(w, 1e6, domain, grid)).toEqual({ start: T0 + 82800, end: T0 + 86400 });
  });

  it('resizes one edge and never below one bin', () => {
    expect(resizeWindow(w, 'end', T0 + 10000, domain, grid)).toEqual({ start: T0 + 3600, end: T0 + 9900 });
    expect(resizeWindow(w, 'start', T0 + 9000, domain, grid)).toEqual({ start: T0 + 6300, end: T0 + 7200 });
    expect(resizeWindow(w, 'end', T0, domain, grid)).toEqual({ start: T0 + 3600, end: T0 + 4500 });
  });
});

describe('hit testing and bins', () => {
  it('finds edges, inside and outside', () => {
    const px = { x0: 100, x1: 200 };
    expect(hitTest(50, null)).toBe('new');
    expect(hitTest(104, px)).toBe('start');
    expect(hitTest(197, px)).toBe('end');
    expect(hitTest(150, px)).toBe('move');
    expect(hitTest(250, px)).toBe('new');
  });

  it('tells which bins overlap the half-open window', () => {
    const w = { start: T0 + 900, end: T0 + 2700 };
    expect([0, 1, 2, 3].map((i) => binInWindow(i, grid, w))).toEqual([false, true, true, false]);
  });

  it('treats a window over the whole domain as no window', () => {
    expect(coversDomain(domain, domain)).toBe(true);
    expect(coversDomain({ start: T0, end: T0 + 900 }, domain)).toBe(false);
  });
});

describe('zoomable axis, second resolution and typed times', () => {
  const dom = { start: T0, end: T0 + 86400 };
  it('a drag on the second grid keeps its seconds (no snapping to bins)', () => {
    expect(windowFromDrag(T0 + 3600.4, T0 + 4200.6, dom, SECOND_GRID)).toEqual({ start: T0 + 3600, end: T0 + 4201 });
    expect(resizeWindow({ start: T0 + 10, end: T0 + 20 }, 'end', T0 + 612, dom, SECOND_GRID)).toEqual({ start: T0 + 10, end: T0 + 612 });
  });
  it('zooms about a time that keeps its place, within the domain and down to MIN_VIEW_SECONDS', () => {
    const v = zoomView(dom, dom, T0 + 43200, 4);
    expect(v).toEqual({ start: T0 + 43200 - 10800, end: T0 + 43200 + 10800 });
    // at stays at the same fraction of the view
    const w = zoomView(dom, dom, T0 + 21600, 2);
    expect((T0 + 21600 - w.start) / (w.end - w.start)).toBeCloseTo(0.25, 12);
    expect(zoomView(dom, dom, T0 + 100, 1e9).end - zoomView(dom, dom, T0 + 100, 1e9).start).toBe(MIN_VIEW_SECONDS);
    expect(zoomView(v, dom, T0, 1e-6)).toEqual(dom);
    expect(clampView({ start: T0 - 50, end: T0 + 50 }, dom)).toEqual({ start: T0, end: T0 + 100 });
  });
  it('nudges by a round step about 1/100 of the view', () => {
    expect(nudgeStep(dom)).toBe(300);
    expect(nudgeStep({ start: 0, end: 600 })).toBe(5);
    expect(nudgeStep({ start: 0, end: 60 })).toBe(1);
  });
  it('parses ISO 8601, UTC without a zone, offsets, and refuses impossible dates', () => {
    expect(parseIsoUtc('2018-01-01T00:00:00Z')).toBe(T0);
    expect(parseIsoUtc('2018-01-01 10:15')).toBe(T0 + 36900);
    expect(parseIsoUtc('2018-01-01T11:15:30+01:00')).toBe(T0 + 36930);
    expect(parseIsoUtc('2018-01-01')).toBe(T0);
    expect(parseIsoUtc('2018-02-30T00:00Z')).toBeNull();
    expect(parseIsoUtc('2018-01-01T24:00')).toBeNull();
    expect(parseIsoUtc('yesterday')).toBeNull();
    expect(formatIsoUtc(T0 + 36930)).toBe('2018-01-01T10:15:30Z');
    expect(parseIsoUtc(formatIsoUtc(T0 + 12345))).toBe(T0 + 12345);
  });
});
