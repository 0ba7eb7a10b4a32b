import { describe, expect, it } from 'vitest';
import { trimTail } from './histogram';

describe('trimTail', () => {
  it('drops empty trailing bins', () => {
    expect(trimTail([5, 3, 0, 0])).toEqual({ keep: 2, hidden: 0 });
  });

  it('drops a sparse tail of outliers but keeps the bulk', () => {
    const counts = [1000, 2000, 3000, 2000, 0, 1, 0, 2, 1];
    expect(trimTail(counts, 0.001)).toEqual({ keep: 4, hidden: 4 });
  });

  it('keeps at least one bin', () => {
    expect(trimTail([0, 0, 0])).toEqual({ keep: 1, hidden: 0 });
    expect(trimTail([7])).toEqual({ keep: 1, hidden: 0 });
  });
});
