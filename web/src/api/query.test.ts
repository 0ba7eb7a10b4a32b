import { describe, expect, it } from 'vitest';
import {
  EMPTY_FILTERS,
  buildQuery,
  datasetNameFromFile,
  densityTileTemplate,
  normalizeBBox,
  normalizeCallsign,
  normalizeIcao24,
  parseFilters,
  parseRender,
  validateFilters,
  type Filters,
} from './query';

const f = (patch: Partial<Filters>): Filters => ({ ...EMPTY_FILTERS, ...patch });

describe('buildQuery', () => {
  it('is empty without filters', () => {
    expect(buildQuery(f({})).toString()).toBe('');
  });

  it('writes every filter in a fixed order', () => {
    const q = buildQuery(
      f({
        onGround: 'false',
        callsign: 'afr*',
        icao24: '4CA7B5',
        altMax: 38000,
        altMin: 10000,
        t1: 1514800800.4,
        t0: 1514786400.6,
        bbox: [-10, 35, 30, 60],
      }),
    );
    expect([...q.keys()]).toEqual(['bbox', 't0', 't1', 'alt_min', 'alt_max', 'alt_unit', 'icao24', 'callsign', 'on_ground']);
    expect(q.get('bbox')).toBe('-10,35,30,60');
    // Half-open window widened to whole seconds: t0 down, t1 up.
    expect(q.get('t0')).toBe('1514786400');
    expect(q.get('t1')).toBe('1514800801');
    expect(q.get('alt_unit')).toBe('ft');
    expect(q.get('icao24')).toBe('4ca7b5');
    expect(q.get('callsign')).toBe('AFR*');
    expect(q.get('on_ground')).toBe('false');
  });

  it('sends alt_unit only with an altitude bound, and keeps a one-sided band', () => {
    expect(buildQuery(f({ altMin: 0 })).toString()).toBe('alt_min=0&alt_unit=ft');
    expect(buildQuery(f({ altMax: 5000 })).toString()).toBe('alt_max=5000&alt_unit=ft');
  });

  it('can leave out the time window and the bbox', () => {
    const filters = f({ t0: 10, t1: 20, bbox: [1, 2, 3, 4], altMin: 100 });
    expect(buildQuery(filters, { withoutTime: true }).toString()).toBe('bbox=1%2C2%2C3%2C4&alt_min=100&alt_unit=ft');
    expect(buildQuery(filters, { withoutBBox: true }).toString()).toBe('t0=10&t1=20&alt_min=100&alt_unit=ft');
  });

  it('round-trips through parseFilters', () => {
    const filters = f({ t0: 100, t1: 200, altMin: 1000, altMax: 2000, callsign: 'BAW', icao24: 'abc123,def456', onGround: 'true', bbox: [1, 2, 3, 4] });
    expect(parseFilters(buildQuery(filters))).toEqual(filters);
  });
});

describe('normalizers', () => {
  it('clamps and rounds a map view', () => {
    expect(normalizeBBox([-200.123456, -89, 190, 89])).toEqual([-180, -85.0511, 180, 85.0511]);
    expect(normalizeBBox([2.123456, 48.987654, 3.5, 49.1])).toEqual([2.1235, 48.9877, 3.5, 49.1]);
  });

  it('upper-cases callsigns and joins a list with commas', () => {
    expect(normalizeCallsign(' aal12* ')).toBe('AAL12*');
    expect(normalizeCallsign('baw, afr  klm')).toBe('BAW,AFR,KLM');
    expect(normalizeCallsign('   ')).toBe('');
  });

  it('lower-cases and deduplicates icao24 addresses', () => {
    expect(normalizeIcao24('A1B2C3 a1b2c3; 4CA7B5')).toBe('a1b2c3,4ca7b5');
  });
});

describe('parse', () => {
  it('converts metres to feet and ignores junk', () => {
    const p = parseFilters(new URLSearchParams('alt_min=3048&alt_unit=m&t0=abc&on_ground=maybe&bbox=1,2,3'));
    expect(p.altMin).toBe(10000);
    expect(p.t0).toBeNull();
    expect(p.onGround).toBe('any');
    expect(p.bbox).toBeNull();
  });

  it('falls back to default render options', () => {
    expect(parseRender(new URLSearchParams('value=speed&how=bogus&cmap=magma'))).toEqual({ value: 'speed', how: 'eq_hist', cmap: 'magma' });
  });
});

describe('densityTileTemplate', () => {
  it('keeps the {z}/{x}/{y} placeholders and appends the render options', () => {
    const t = densityTileTemplate('http://127.0.0.1:8080', 'europe', new URLSearchParams('t0=1&t1=2'), { value: 'count', how: 'log', cmap: 'viridis' });
    expect(t).toBe('http://127.0.0.1:8080/tiles/europe/density/{z}/{x}/{y}.png?t0=1&t1=2&value=count&how=log&cmap=viridis&size=256');
  });
});

describe('datasetNameFromFile', () => {
  it('strips data extensions and keeps [a-z0-9_-]', () => {
    expect(datasetNameFromFile('traffic_europe_20180101_m3.so6.gz')).toBe('traffic_europe_20180101_m3');
    expect(datasetNameFromFile('C:\\data\\My Flights (2).CSV')).toBe('my-flights-2');
    expect(datasetNameFromFile('...json')).toBe('dataset');
    expect(datasetNameFromFile(`${'a'.repeat(70)}.csv`)).toHaveLength(64);
  });
});

describe('validateFilters', () => {
  it('accepts empty and sensible filters', () => {
    expect(validateFilters(f({}))).toBeNull();
    expect(validateFilters(f({ altMin: 0, altMax: 0, t0: 1, t1: 2, icao24: '4CA7B5, a1b2c3' }))).toBeNull();
  });

  it('names the parameter of an impossible band, window or address', () => {
    expect(validateFilters(f({ altMin: 40000, altMax: 20000 }))?.param).toBe('alt_min');
    expect(validateFilters(f({ t0: 5, t1: 5 }))?.param).toBe('t0');
    expect(validateFilters(f({ icao24: '4ca7b5,xyz' }))).toEqual({
      param: 'icao24',
      detail: 'Not a 24-bit hex address: xyz (six hex digits, e.g. 4ca7b5).',
    });
  });

  it('refuses a callsign the server would (one pattern of [A-Z0-9*?], at most 16 characters)', () => {
    expect(validateFilters(f({ callsign: 'afr*' }))).toBeNull();
    expect(validateFilters(f({ callsign: 'BAW1?' }))).toBeNull();
    expect(validateFilters(f({ callsign: 'AF-R' }))?.param).toBe('callsign');
    expect(validateFilters(f({ callsign: 'AFR, BAW' }))?.param).toBe('callsign');
    expect(validateFilters(f({ callsign: 'A'.repeat(17) }))?.param).toBe('callsign');
    expect(validateFilters(f({ callsign: 'A'.repeat(16) }))).toBeNull();
  });
});
