import { describe, expect, it } from 'vitest';
import { aoiPath, closesPolygon, dragRect, fitTransform, fixationRadius, maxFixationMs, nextAoiName, paintedPixels, scanpathSpanMs, tileZoom, visibleTiles } from './geometry';

describe('tile zoom', () => {
  it('is the zoom at about one tile pixel per CSS pixel', () => {
    // 1024-px stimulus at 0.25 CSS px per stimulus px: 256 CSS px across, zoom 0.
    expect(tileZoom(0.25, 1024)).toBe(0);
    expect(tileZoom(1, 1024)).toBe(2);
    expect(tileZoom(2, 1024)).toBe(3);
    expect(tileZoom(0.01, 1024)).toBe(0);
    expect(tileZoom(1000, 1024)).toBe(6);
    expect(tileZoom(Number.NaN, 1024)).toBe(0);
  });
});

describe('visible tiles', () => {
  it('covers the stimulus at zoom 0 with one tile', () => {
    expect(visibleTiles(0, 1024, 768, { x0: -50, y0: -50, x1: 2000, y1: 2000 })).toEqual([{ z: 0, x: 0, y: 0, x0: 0, y0: 0, size: 1024 }]);
  });

  it('leaves out the rows below a landscape stimulus', () => {
    // 1024 × 768 at zoom 2: 256-px tiles, rows 0..2 hold the image, row 3 lies below it.
    const t = visibleTiles(2, 1024, 768, { x0: 0, y0: 0, x1: 1024, y1: 1024 });
    expect(t).toHaveLength(12);
    expect(Math.max(...t.map((r) => r.y))).toBe(2);
  });

  it('keeps only the tiles meeting the view, by brute force over all tiles', () => {
    const view = { x0: 300, y0: 100, x1: 700, y1: 500 };
    const z = 3;
    const size = 1024 / 8;
    const brute: string[] = [];
    for (let y = 0; y < 8; y++)
      for (let x = 0; x < 8; x++) {
        const meets = x * size < view.x1 && (x + 1) * size > view.x0 && y * size < view.y1 && (y + 1) * size > view.y0 && y * size < 768;
        if (meets) brute.push(`${x},${y}`);
      }
    expect(visibleTiles(z, 1024, 768, view).map((r) => `${r.x},${r.y}`)).toEqual(brute);
  });
});

describe('fixation circles', () => {
  it('have areas proportional to duration between rMin and rMax', () => {
    const r = fixationRadius(400, 4, 28);
    expect(r(0)).toBe(4);
    expect(r(400)).toBe(28);
    expect(r(800)).toBe(28);
    // sqrt: a quarter of the longest duration is halfway in radius.
    expect(r(100)).toBeCloseTo(16, 9);
    expect(maxFixationMs([{ fixations: [{ x: 0, y: 0, t_start_ms: 0, duration_ms: 120 }] }, { fixations: [{ x: 0, y: 0, t_start_ms: 0, duration_ms: 340 }] }])).toBe(340);
    expect(maxFixationMs([])).toBe(0);
  });
});

describe('AOI drawing', () => {
  it('a drag spans a clipped rectangle, either direction', () => {
    expect(dragRect([200, 150], [10, 20], 1024, 768)).toEqual([10, 20, 200, 150]);
    expect(dragRect([-10, -10], [2000, 900], 1024, 768)).toEqual([0, 0, 1024, 768]);
    expect(dragRect([5, 5], [5.5, 100], 1024, 768)).toBeNull();
  });

  it('a polygon closes near its first vertex once it has three', () => {
    expect(closesPolygon([[0, 0], [10, 0]], [0, 0], 5)).toBe(false);
    expect(closesPolygon([[0, 0], [10, 0], [10, 10]], [3, 3], 5)).toBe(true);
    expect(closesPolygon([[0, 0], [10, 0], [10, 10]], [6, 6], 5)).toBe(false);
  });

  it('paths and names', () => {
    expect(aoiPath({ name: 'a', rect: [1, 2, 3, 4] })).toBe('M1,2L3,2L3,4L1,4Z');
    expect(aoiPath({ name: 'p', polygon: [[0, 0], [5, 0], [0, 5]] })).toBe('M0,0L5,0L0,5Z');
    expect(nextAoiName([])).toBe('AOI 1');
    expect(nextAoiName(['AOI 1', 'AOI 3'])).toBe('AOI 2');
  });
});

describe('view helpers', () => {
  it('counts painted pixels by alpha', () => {
    const px = new Uint8ClampedArray([0, 0, 0, 0, 255, 0, 0, 1, 9, 9, 9, 0, 1, 2, 3, 255]);
    expect(paintedPixels(px)).toBe(2);
  });

  it('fits the stimulus centred', () => {
    const t = fitTransform(1024, 768, 1040, 800, 8);
    expect(t.k).toBe(1);
    expect(t.x).toBe(8);
    expect(t.y).toBe(16);
  });
});

describe('scanpath span', () => {
  it('is the longest first-to-last fixation start', () => {
    const f = (t: number) => ({ x: 0, y: 0, t_start_ms: t, duration_ms: 10 });
    expect(scanpathSpanMs([{ fixations: [f(100), f(400), f(900)] }, { fixations: [f(5000), f(5300)] }, { fixations: [f(7)] }, { fixations: [] }])).toBe(800);
    expect(scanpathSpanMs([])).toBe(0);
  });
});
