import { describe, expect, it } from 'vitest';
import {
  formatAltitude,
  formatBytes,
  formatCompact,
  formatDuration,
  formatFlightLevel,
  formatHoursMinutes,
  formatInt,
  formatSpeed,
  formatUtc,
  formatUtcTime,
  formatWindow,
} from './format';

describe('numbers', () => {
  it('groups thousands', () => {
    expect(formatInt(11043)).toBe('11,043');
    expect(formatInt(15_000_000)).toBe('15,000,000');
    expect(formatInt(2.5)).toBe('3');
    expect(formatInt(NaN)).toBe('–');
    expect(formatInt(null)).toBe('–');
  });

  it('abbreviates with three significant digits', () => {
    expect(formatCompact(950)).toBe('950');
    expect(formatCompact(1234)).toBe('1.23k');
    expect(formatCompact(12_700)).toBe('12.7k');
    expect(formatCompact(127_672)).toBe('128k');
    expect(formatCompact(999_700)).toBe('1.00M');
    expect(formatCompact(15_000_000)).toBe('15.0M');
    expect(formatCompact(-2500)).toBe('-2.50k');
  });

  it('formats bytes in SI units', () => {
    expect(formatBytes(512)).toBe('512 B');
    expect(formatBytes(4_384_969)).toBe('4.4 MB');
    expect(formatBytes(19_257_893)).toBe('19 MB');
  });
});

describe('time', () => {
  const t = 1514787300; // 2018-01-01 06:15:00 UTC

  it('prints UTC', () => {
    expect(formatUtc(t)).toBe('2018-01-01 06:15');
    expect(formatUtcTime(t)).toBe('06:15');
  });

  it('prints durations coarsely', () => {
    expect(formatDuration(12)).toBe('12 s');
    expect(formatDuration(45 * 60)).toBe('45 min');
    expect(formatDuration(6 * 3600 + 15 * 60)).toBe('6 h 15 min');
    expect(formatDuration(3 * 3600)).toBe('3 h');
    expect(formatDuration(51 * 3600)).toBe('2 d 3 h');
    expect(formatDuration(-1)).toBe('–');
  });

  it('prints h:mm for tables', () => {
    expect(formatHoursMinutes(86 * 60)).toBe('1:26');
    expect(formatHoursMinutes(5 * 60 + 29)).toBe('0:05');
    expect(formatHoursMinutes(26 * 3600)).toBe('26:00');
  });

  it('repeats the date in a window only when it changes', () => {
    expect(formatWindow(t, t + 6 * 3600)).toBe('2018-01-01 06:15 → 12:15 UTC');
    expect(formatWindow(t, t + 86400)).toBe('2018-01-01 06:15 → 2018-01-02 06:15 UTC');
  });
});

describe('aviation units', () => {
  it('converts metres to feet and flight levels', () => {
    expect(formatAltitude(11277.6)).toBe('37,000 ft');
    expect(formatFlightLevel(11277.6)).toBe('FL370');
    expect(formatFlightLevel(300)).toBe('FL010');
    expect(formatFlightLevel(-50)).toBe('FL000');
  });

  it('converts m/s to knots', () => {
    expect(formatSpeed(231.5)).toBe('450 kt');
    expect(formatSpeed(undefined)).toBe('–');
  });
});
