import { describe, expect, it } from 'vitest';
import { parseBundleView, writeBundleView } from './bundlePanel';

describe('bundle view in the hash', () => {
  it('leaves defaults out and reads them back', () => {
    const p = new URLSearchParams('dataset=demo');
    writeBundleView(p, { id: 'b7', mode: 'bundled', relaxation: 0, color: 'length' });
    expect(p.toString()).toBe('dataset=demo&bundle=b7');
    expect(parseBundleView(p)).toEqual({ id: 'b7', mode: 'bundled', relaxation: 0, color: 'length' });
  });

  it('keeps a raw view, a relaxation to hundredths and a colour mode', () => {
    const p = new URLSearchParams();
    writeBundleView(p, { id: 'b12', mode: 'raw', relaxation: 0.3456, color: 'direction' });
    expect(p.toString()).toBe('bundle=b12&bview=raw&brelax=0.35&bcolor=direction');
    expect(parseBundleView(p)).toEqual({ id: 'b12', mode: 'raw', relaxation: 0.35, color: 'direction' });
  });

  it('writes nothing without a shown bundle', () => {
    const p = new URLSearchParams('a=1');
    writeBundleView(p, null);
    expect(p.toString()).toBe('a=1');
  });

  it('refuses a malformed id and clamps or defaults the rest', () => {
    expect(parseBundleView(new URLSearchParams('bview=raw'))).toBeNull();
    expect(parseBundleView(new URLSearchParams('bundle=../etc'))).toBeNull();
    expect(parseBundleView(new URLSearchParams('bundle=b1&brelax=7&bcolor=plaid&bview=x'))).toEqual({ id: 'b1', mode: 'bundled', relaxation: 1, color: 'length' });
    expect(parseBundleView(new URLSearchParams('bundle=b1&brelax=-1'))?.relaxation).toBe(0);
    expect(parseBundleView(new URLSearchParams('bundle=b1&brelax=nan'))?.relaxation).toBe(0);
  });
});
