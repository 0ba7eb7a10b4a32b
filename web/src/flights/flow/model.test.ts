import { describe, expect, it } from 'vitest';
import { headingColor, levelOpacity, lineWidth, linesAt, toFeatures, type FlowLine } from './model';

const line = (points: [number, number][], traffic = 1, heading: number | null = 90): FlowLine => ({ sector: 2, heading, traffic, points });

describe('flow model', () => {
  it('fades the density out and the lines in between levels 0 and 1', () => {
    expect(levelOpacity(0)).toEqual({ density: 1, lines: 0 });
    expect(levelOpacity(0.25)).toEqual({ density: 0.75, lines: 0.25 });
    expect(levelOpacity(1)).toEqual({ density: 0, lines: 1 });
    expect(levelOpacity(2)).toEqual({ density: 0, lines: 1 });
    expect(levelOpacity(-1)).toEqual({ density: 1, lines: 0 });
  });

  it('slides each point from its streamline to its bundle between levels 1 and 2', () => {
    const s = [line([[0, 0], [10, 0]])];
    const b = [line([[0, 4], [10, 8]])];
    expect(linesAt(s, b, 0.5)[0].points).toEqual([[0, 0], [10, 0]]);
    expect(linesAt(s, b, 1)[0].points).toEqual([[0, 0], [10, 0]]);
    expect(linesAt(s, b, 1.25)[0].points).toEqual([[0, 1], [10, 2]]);
    expect(linesAt(s, b, 2)[0].points).toEqual([[0, 4], [10, 8]]);
    expect(() => linesAt(s, [], 1.5)).toThrow(/differ in number/);
    expect(() => linesAt(s, [line([[0, 0]])], 1.5)).toThrow(/line 0/);
  });

  it('colours by heading as the server does (hue = heading / 360)', () => {
    expect(headingColor(0)).toBe('#ff2626');
    expect(headingColor(120)).toBe('#26ff26');
    expect(headingColor(240)).toBe('#2626ff');
    expect(headingColor(360)).toBe(headingColor(0));
    expect(headingColor(null)).toBe('#d9d9d9');
  });

  it('weights lines by traffic and draws the main flows last', () => {
    expect(lineWidth(4, 4)).toBeCloseTo(3);
    expect(lineWidth(1, 4)).toBeCloseTo(1.5 * (0.5 + 0.75));
    expect(lineWidth(0, 0)).toBeCloseTo(0.75);
    const fc = toFeatures([line([[0, 0], [1, 1]], 9), line([[2, 2], [3, 3]], 1, 270)]);
    expect(fc.features.map((f) => f.properties?.width)).toEqual([lineWidth(1, 9), lineWidth(9, 9)]);
    expect(fc.features[1].geometry.coordinates).toEqual([[0, 0], [1, 1]]);
  });
});
