import { describe, expect, it } from 'vitest';
import { ms, transitionShade } from './aoiPanel';

describe('AOI table cells', () => {
  it('milliseconds, undefined as a dash', () => {
    expect(ms(null)).toBe('–');
    expect(ms(undefined)).toBe('–');
    expect(ms(Number.NaN)).toBe('–');
    expect(ms(0)).toBe('0 ms');
    expect(ms(1234.6)).toBe('1,235 ms');
  });

  it('transition shades run from the panel colour at 0 to the accent at the largest count', () => {
    const s = transitionShade([
      [0, 4],
      [2, 0],
    ]);
    expect(s(0)).toBe('rgb(22, 27, 34)');
    expect(s(4)).toBe('rgb(255, 138, 31)');
    expect(s(9)).toBe('rgb(255, 138, 31)');
    // An all-zero matrix stays at the panel colour.
    expect(transitionShade([[0]])(0)).toBe('rgb(22, 27, 34)');
  });
});
