import { describe, expect, it } from 'vitest';
import { choosePerplexity, perplexityCap } from './tsne';

describe('t-SNE perplexity rule', () => {
  it('caps at (N − 1) / 3 so that 3·perplexity neighbours exist', () => {
    // 20 runs: 19 / 3 = 6.333…; the server refuses 3·p > N − 1.
    expect(perplexityCap(20)).toBe(6.33);
    expect(3 * perplexityCap(20)! <= 19).toBe(true);
    expect(perplexityCap(91)).toBe(30);
    expect(perplexityCap(1000)).toBe(100);
    expect(perplexityCap(3)).toBeNull();
    expect(perplexityCap(4)).toBe(1);
  });
  it('sends the request when it fits, the cap with a note when not, nothing below 4 rows', () => {
    expect(choosePerplexity(5, 20)).toMatchObject({ value: 5, capped: false });
    expect(choosePerplexity(30, 20)).toMatchObject({ value: 6.33, capped: true });
    expect(choosePerplexity(30, 20).note).toContain('capped to 6.33');
    expect(choosePerplexity(30, 3).value).toBeNull();
    expect(choosePerplexity(0.2, 100).value).toBe(1);
  });
});
