import { describe, expect, it } from 'vitest';
import { EMPTY_FILTERS } from '../api/query';
import { legendGradient, legendLabel, legendTicks } from './playbackLegend';
import { playbackAction, type KeyLike } from './playbackKeys';
import { formatInstant, trafficFilter } from './playback';

const key = (k: string, mods: Partial<KeyLike> = {}): KeyLike => ({ key: k, shiftKey: false, ctrlKey: false, metaKey: false, altKey: false, ...mods });

describe('playback keys', () => {
  it('space, arrows, shift+arrows, + and -', () => {
    expect(playbackAction(key(' '))).toEqual({ kind: 'toggle' });
    expect(playbackAction(key('ArrowLeft'))).toEqual({ kind: 'step', seconds: -1 });
    expect(playbackAction(key('ArrowRight'))).toEqual({ kind: 'step', seconds: 1 });
    expect(playbackAction(key('ArrowLeft', { shiftKey: true }))).toEqual({ kind: 'step', seconds: -60 });
    expect(playbackAction(key('ArrowRight', { shiftKey: true }))).toEqual({ kind: 'step', seconds: 60 });
    expect(playbackAction(key('+', { shiftKey: true }))).toEqual({ kind: 'faster' });
    expect(playbackAction(key('='))).toEqual({ kind: 'faster' });
    expect(playbackAction(key('-'))).toEqual({ kind: 'slower' });
    expect(playbackAction(key('Escape'))).toEqual({ kind: 'release' });
  });

  it('leaves browser shortcuts and other keys alone', () => {
    expect(playbackAction(key('ArrowLeft', { altKey: true }))).toBeNull(); // history back
    expect(playbackAction(key('+', { ctrlKey: true }))).toBeNull(); // zoom
    expect(playbackAction(key('a'))).toBeNull();
  });
});

describe('the legend', () => {
  it('labels values in the dashboard units', () => {
    expect(legendLabel('altitude', 10668)).toBe('FL350');
    expect(legendLabel('altitude', 0)).toBe('FL000');
    expect(legendLabel('speed', 250)).toBe('486 kt'); // 250 m/s × 3600/1852
    expect(legendLabel('vrate', 10.16)).toBe('+2,000 ft/min'); // 10.16 m/s = 2000 ft/min
    expect(legendLabel('vrate', -5.08)).toBe('-1,000 ft/min');
    expect(legendLabel('vrate', 0)).toBe('0 ft/min');
    expect(legendLabel('callsign', 'DLH')).toBe('DLH');
    expect(legendLabel('callsign', '')).toBe('other');
  });

  it('places numeric stops by value and keeps categorical ones in order', () => {
    const t = legendTicks({
      colorBy: 'altitude',
      unit: 'm',
      stops: [
        { value: 0, color: '#000' },
        { value: 3000, color: '#111' },
        { value: 12000, color: '#222' },
      ],
    });
    expect(t.map((x) => x.at)).toEqual([0, 0.25, 1]);
    expect(t.map((x) => x.label)).toEqual(['FL000', 'FL098', 'FL394']);
    expect(legendGradient(t)).toBe('linear-gradient(to right, #000 0.0%, #111 25.0%, #222 100.0%)');
    const c = legendTicks({
      colorBy: 'callsign',
      unit: '',
      stops: [
        { value: 'RYR', color: '#a' },
        { value: '', color: '#b' },
      ],
    });
    expect(c).toEqual([
      { label: 'RYR', color: '#a', at: null },
      { label: 'other', color: '#b', at: null },
    ]);
  });
});

describe('filters during playback', () => {
  it('altitude band in metres, callsign prefix, bbox', () => {
    expect(trafficFilter({ ...EMPTY_FILTERS }, null)).toEqual({});
    const f = trafficFilter({ ...EMPTY_FILTERS, altMin: 20000, altMax: 40000, callsign: ' dlh ' }, [1, 2, 3, 4]);
    expect(f).toEqual({ altMinM: 6096, altMaxM: 12192, callsign: 'DLH', bbox: [1, 2, 3, 4] });
    // The pattern goes whole (the API's rule applies it), and the addresses as the API's query has them.
    expect(trafficFilter({ ...EMPTY_FILTERS, callsign: 'baw1*' }, null).callsign).toBe('BAW1*');
    expect(trafficFilter({ ...EMPTY_FILTERS, callsign: '*X' }, null).callsign).toBe('*X');
    expect(trafficFilter({ ...EMPTY_FILTERS, icao24: '4CA7B5 a1b2c3' }, null).icao24).toEqual(['4ca7b5', 'a1b2c3']);
  });
});

describe('the instant readout', () => {
  it('shows seconds, and tenths when the instant has a fraction', () => {
    expect(formatInstant(1514851199.5)).toBe('2018-01-01 23:59:59.5');
    expect(formatInstant(1514851199)).toBe('2018-01-01 23:59:59');
    expect(formatInstant(1514764800.05)).toBe('2018-01-01 00:00:00.0');
    expect(formatInstant(NaN)).toBe('–');
  });
});
