import { describe, expect, it } from 'vitest';
import { normalizeParam } from './replay';

describe('normalizeParam', () => {
  it('accepts the server spelling `default` and fills missing fields', () => {
    expect(normalizeParam({ name: 'a_min', default: 40, min: 0, max: 10000, integer: false, unit: '', help: 'h' })).toEqual({
      name: 'a_min',
      unit: '',
      default_value: 40,
      min: 0,
      max: 10000,
      integer: false,
      help: 'h',
    });
    expect(normalizeParam({ name: 'n', default_value: 4, integer: true }).default_value).toBe(4);
    expect(normalizeParam({ name: 'n' }).max).toBe(Infinity);
  });
});
