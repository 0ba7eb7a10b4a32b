import { describe, expect, it } from 'vitest';
import { formatAois, gazeHash, isGazeHash, parseAois, parseGazeHash } from './route';
import { dashboardOf } from '../route';

describe('gaze hash', () => {
  it('is recognised only as #gaze…', () => {
    expect(isGazeHash('#gaze')).toBe(true);
    expect(isGazeHash('#gaze?g=lund')).toBe(true);
    expect(isGazeHash('#gazer')).toBe(false);
    expect(dashboardOf('#gaze?g=x')).toBe('gaze');
    expect(dashboardOf('#gazex')).toBe('map');
  });

  it('defaults when empty', () => {
    const r = parseGazeHash('#gaze');
    expect(r).toEqual({
      dataset: null,
      stimulus: null,
      participant: null,
      t0: null,
      t1: null,
      method: 'ivt',
      types: ['fixation', 'saccade'],
      what: 'fixations',
      how: 'log',
      aois: [],
    });
    expect(gazeHash(r)).toBe('#gaze');
  });

  it('round-trips every field, AOIs included', () => {
    const h = '#gaze?g=lund&stimulus=Europe&participant=TH34&t0=100&t1=2500&method=idt&types=fixation&what=samples&how=eq_hist&aoi=face:r:10,20,200,180;sky:p:0,0,1024,0,512,300.5';
    const r = parseGazeHash(h);
    expect(r.dataset).toBe('lund');
    expect(r.t0).toBe(100);
    expect(r.t1).toBe(2500);
    expect(r.method).toBe('idt');
    expect(r.types).toEqual(['fixation']);
    expect(r.aois).toEqual([
      { name: 'face', rect: [10, 20, 200, 180] },
      { name: 'sky', polygon: [[0, 0], [1024, 0], [512, 300.5]] },
    ]);
    expect(gazeHash(r)).toBe(h);
  });

  it('drops malformed values', () => {
    const r = parseGazeHash('#gaze?t0=-5&t1=abc&method=xyz&types=fixation,bogus&how=cubic');
    expect(r.t0).toBeNull();
    expect(r.t1).toBeNull();
    expect(r.method).toBe('ivt');
    expect(r.types).toEqual(['fixation']);
    expect(r.how).toBe('log');
    // t1 not after t0 is no window end.
    expect(parseGazeHash('#gaze?t0=500&t1=400').t1).toBeNull();
  });
});

describe('AOIs in the hash', () => {
  it('normalises rectangles to x0 < x1, y0 < y1 and rounds to hundredths', () => {
    expect(parseAois('a:r:200,180,10,20')).toEqual([{ name: 'a', rect: [10, 20, 200, 180] }]);
    expect(formatAois([{ name: 'a', rect: [1.23456, 2, 3, 4] }])).toBe('a:r:1.23,2,3,4');
  });

  it('rejects empty rectangles, short polygons, bad names and duplicates', () => {
    expect(parseAois('a:r:1,1,1,5')).toEqual([]);
    expect(parseAois('a:p:0,0,1,1')).toEqual([]);
    expect(parseAois('a:p:0,0,1,1,2')).toEqual([]);
    expect(parseAois('<b>:r:0,0,1,1')).toEqual([]);
    expect(parseAois('a:r:0,0,1,1;a:r:0,0,2,2')).toEqual([{ name: 'a', rect: [0, 0, 1, 1] }]);
    expect(parseAois('a:r:0,0,x,1;b:r:0,0,3,3')).toEqual([{ name: 'b', rect: [0, 0, 3, 3] }]);
  });

  it('keeps names with spaces through URLSearchParams', () => {
    const aois = [{ name: 'AOI 1', rect: [0, 0, 10, 10] as [number, number, number, number] }];
    expect(parseGazeHash(gazeHash({ aois })).aois).toEqual(aois);
  });
});
