import { describe, expect, it } from 'vitest';
import { bearingColor, bundleLegend, cubuRainbow, densityTicks, hsvCss, dropCrowded, kmPerMercatorDegree, linearTicks, normalizeSpan, type DensityLegendAnswer } from './legend';

/** A legend answer: span 1…10, stops at k/20 whose values are the quantiles the server computed. */
const stops = Array.from({ length: 21 }, (_, k) => ({ t: k / 20, value: 1 + (9 * (k / 20)) ** 2 / 9, color: '#000000' }));
const SPAN: DensityLegendAnswer = {
  empty: false,
  lo: 1,
  hi: 10,
  value: 'count',
  how: 'eq_hist',
  z: 5,
  unit: 'segments per pixel',
  min_level: 0.25,
  stops,
};

describe('normalizeSpan (the server shade.hpp formulas)', () => {
  it('linear and log by their formulas, clamped at the ends', () => {
    expect(normalizeSpan(SPAN, 5.5, 'linear')).toBeCloseTo(0.5, 12);
    expect(normalizeSpan(SPAN, 0, 'linear')).toBe(0);
    expect(normalizeSpan(SPAN, 99, 'log')).toBe(1);
    // log1p: (ln 4 − ln 2) / (ln 11 − ln 2)
    expect(normalizeSpan(SPAN, 3, 'log')).toBeCloseTo((Math.log(4) - Math.log(2)) / (Math.log(11) - Math.log(2)), 12);
  });
});

describe('densityTicks', () => {
  it('eq_hist: the stops at the quartiles, labelled with their values', () => {
    const t = densityTicks(SPAN, 'eq_hist');
    expect(t.map((x) => x.at)).toEqual([0, 0.25, 0.5, 0.75, 1]);
    expect(t.map((x) => x.label)).toEqual(['1', '1.6', '3.3', '6.1', '10']);
  });
  it('linear: round values where the linear formula puts them, ends labelled', () => {
    const t = densityTicks({ ...SPAN, lo: 0, hi: 1000, how: 'linear' }, 'linear');
    for (const x of t) expect(x.at).toBeCloseTo(Number(x.label.replace(/,/g, '')) / 1000, 12);
    expect(t[0]!.label).toBe('0');
    expect(t[t.length - 1]!.label).toBe('1,000');
  });
  it('altitude in flight levels, speed in knots', () => {
    const alt = densityTicks({ ...SPAN, value: 'altitude', lo: 0, hi: 12192 }, 'linear');
    expect(alt[alt.length - 1]!.label).toBe('FL400');
    expect(alt.every((x) => /^FL\d{3}$/.test(x.label))).toBe(true);
    const spd = densityTicks({ ...SPAN, value: 'speed', lo: 0, hi: 257.2222 }, 'linear');
    expect(spd[spd.length - 1]!.label).toBe('500 kt');
  });
  it('an empty span has no ticks; a single value one tick', () => {
    expect(densityTicks({ ...SPAN, empty: true }, 'linear')).toEqual([]);
    expect(densityTicks({ ...SPAN, lo: 4, hi: 4 }, 'linear')).toEqual([{ at: 0.5, label: '4' }]);
  });
});

describe('linearTicks and dropCrowded', () => {
  it('round values between the ends', () => {
    expect(linearTicks(0, 40000, 4, String).map((t) => t.label)).toEqual(['0', '10000', '20000', '30000', '40000']);
  });
  it('drops a tick too close to the previous one, keeping the last', () => {
    const t = dropCrowded([
      { at: 0, label: 'a' },
      { at: 0.05, label: 'b' },
      { at: 0.5, label: 'c' },
      { at: 0.95, label: 'd' },
      { at: 1, label: 'e' },
    ]);
    expect(t.map((x) => x.label)).toEqual(['a', 'c', 'e']);
  });
});

describe('cubuRainbow and Mercator lengths', () => {
  it('has the render_math.cpp ends: blue-ish at 0 (off the darkest blue), red-ish at 1', () => {
    // v = 0: w = 0.8 → r = 0, g = 0, b = (3 − 0.2 − 1.2)/2 = 0.8 → 204
    expect(cubuRainbow(0)).toBe('rgb(0, 0, 204)');
    // v = 1: w = 5.2 → r = (3 − 1.2 − 0.2)/2 = 0.8 → 204, g = 0, b = 0
    expect(cubuRainbow(1)).toBe('rgb(204, 0, 0)');
    // v = 0.5: w = 3 → r = 0, g = (4 − 1 − 1)/2 = 1 → 255, b = (3 − 2 − 1)/2 = 0
    expect(cubuRainbow(0.5)).toBe('rgb(0, 255, 0)');
  });
  it('a Mercator degree is 111.32 km at the equator, half that at 60°', () => {
    expect(kmPerMercatorDegree(0)).toBeCloseTo(111.32, 9);
    expect(kmPerMercatorDegree(60)).toBeCloseTo(55.66, 9);
  });
});

describe('bundle colour legends', () => {
  const input = { loKm: 12, hiKm: 830, maxDisplacement: 0.2, cmap: ['#000000', '#ffffff'], width: 200 };
  it('hsvCss is HSV → RGB (the standard sextant formulas)', () => {
    expect(hsvCss(0, 1, 1)).toBe('rgb(255, 0, 0)');
    expect(hsvCss(1 / 3, 1, 1)).toBe('rgb(0, 255, 0)');
    expect(hsvCss(2 / 3, 1, 1)).toBe('rgb(0, 0, 255)');
    expect(hsvCss(1.5, 0, 1)).toBe('rgb(255, 255, 255)');
    expect(hsvCss(-0.25, 1, 1)).toBe(hsvCss(0.75, 1, 1));
  });
  it('direction: east is hue 0 (angle 0 in a y-down plane), north hue 3/4, south 1/4', () => {
    expect(bearingColor(90)).toBe('rgb(255, 0, 0)');
    // hue 3/4: sector 4 at f = 0.5 → (0.5, 0, 1)
    expect(bearingColor(0)).toBe('rgb(128, 0, 255)');
    expect(bearingColor(360)).toBe(bearingColor(0));
    // hue 1/4: sector 1 at f = 0.5 → (0.5, 1, 0)
    expect(bearingColor(180)).toBe('rgb(128, 255, 0)');
    const spec = bundleLegend('direction', input)!;
    expect(spec.ticks.map((t) => t.label)).toEqual(['N 0°', 'E 90°', 'S 180°', 'W 270°', 'N 360°']);
    expect(spec.ticks.map((t) => t.at)).toEqual([0, 0.25, 0.5, 0.75, 1]);
    expect(spec.stops[0]).toBe(spec.stops[spec.stops.length - 1]);
  });
  it('length: km ticks between the shortest and longest trail, placed linearly', () => {
    const spec = bundleLegend('length', input)!;
    for (const t of spec.ticks) {
      const v = Number(t.label.replace(/[≈,]/g, ''));
      expect(t.at).toBeCloseTo((v - 12) / (830 - 12), 9);
    }
    expect(spec.ticks.map((t) => t.label)).toEqual(['≈200', '≈400', '≈600', '≈800']);
  });
  it('density: 0 … 1 of the local maximum; displacement: 0 … 100·max_displacement % of the trail length', () => {
    expect(bundleLegend('density', input)!.ticks.map((t) => t.label)).toEqual(['0', '0.20', '0.40', '0.60', '0.80', '1']);
    const d = bundleLegend('displacement', input)!;
    expect(d.ticks.map((t) => t.label)).toEqual(['0 %', '5 %', '10 %', '15 %', '20 %']);
    expect(d.ticks.map((t) => t.at)).toEqual([0, 0.25, 0.5, 0.75, 1]);
    expect(d.stops).toEqual(input.cmap);
    expect(bundleLegend('displacement', { ...input, maxDisplacement: NaN })).toBeNull();
    expect(bundleLegend('flat', input)).toBeNull();
  });
});
