import { describe, expect, it } from 'vitest';
import type { FeatureCollection } from 'geojson';
import {
  SparseSeries,
  cpaPoint,
  gridFootprints,
  sectorFootprints,
  eventsAt,
  footprintStates,
  occupancyClass,
  parseCsv,
  parseHotspotsCsv,
  parseResult,
  parseSeriesCsv,
  periodEnd,
  periodStart,
  rankHotspots,
  seriesFromCsv,
  stepAt,
  stepsInWindow,
  type Periods,
} from './model';
import type { CongestionResultWire, SeparationEvent, WireHotspot } from './types';

// A deterministic generator for the randomised checks (no shared RNG in the web code; tests only).
function lcg(seed: number) {
  let s = seed >>> 0;
  return () => ((s = (Math.imul(s, 1664525) + 1013904223) >>> 0) / 2 ** 32);
}

/** Brute force: the periods containing t, by scanning every period's [start, end). */
function periodsContaining(p: Periods, t: number): number[] {
  const out: number[] = [];
  for (let k = 0; k < p.steps; k++) if (periodStart(p, k) <= t && t < periodEnd(p, k)) out.push(k);
  return out;
}

describe('stepAt', () => {
  const p: Periods = { t0: 1514764800, t1: 1514764800 + 3600, step: 60, duration: 60, steps: 60 };
  it('finds the period holding t, edges included at the start and excluded at the end', () => {
    expect(stepAt(p, p.t0)).toBe(0);
    expect(stepAt(p, p.t0 + 59.999)).toBe(0);
    expect(stepAt(p, p.t0 + 60)).toBe(1);
    expect(stepAt(p, p.t1 - 0.5)).toBe(59);
    expect(stepAt(p, p.t1)).toBe(-1);
    expect(stepAt(p, p.t0 - 1e-6)).toBe(-1);
    expect(stepAt(p, NaN)).toBe(-1);
  });
  it('is the latest period containing t, against a scan, for overlapping and cut periods', () => {
    const rnd = lcg(7);
    for (const q of [
      { t0: 1000, t1: 1000 + 7 * 300 + 17, step: 300, duration: 900, steps: Math.ceil((7 * 300 + 17) / 300) },
      { t0: 1000, t1: 1000 + 3601, step: 60, duration: 60, steps: 61 },
      { t0: 1000, t1: 1000 + 125, step: 1, duration: 60, steps: 125 },
    ]) {
      for (let i = 0; i < 2000; i++) {
        const t = q.t0 - 10 + rnd() * (q.t1 - q.t0 + 20);
        const scan = periodsContaining(q, t);
        expect(stepAt(q, t)).toBe(scan.length ? scan[scan.length - 1] : -1);
      }
    }
  });
});

describe('stepsInWindow', () => {
  const p: Periods = { t0: 0, t1: 3600, step: 60, duration: 60, steps: 60 };
  it('gives the periods wholly inside the window', () => {
    expect(stepsInWindow(p, 120, 300)).toEqual([2, 4]);
    expect(stepsInWindow(p, 100, 300)).toEqual([2, 4]);
    expect(stepsInWindow(p, -500, 99999)).toEqual([0, 59]);
  });
  it('falls back to the period at the window start for a window shorter than a period', () => {
    expect(stepsInWindow(p, 130, 150)).toEqual([2, 2]);
    expect(stepsInWindow(p, 4000, 5000)).toBeNull();
    expect(stepsInWindow(p, 10, 10)).toBeNull();
  });
  it('gives a hotspot its own periods (duration > step too), against a scan', () => {
    const q: Periods = { t0: 0, t1: 1800, step: 60, duration: 300, steps: 30 };
    for (let first = 0; first < 30; first++) {
      for (let last = first; last < 30; last++) {
        const start = periodStart(q, first);
        const end = periodEnd(q, last);
        const inside: number[] = [];
        for (let k = 0; k < q.steps; k++) if (periodStart(q, k) >= start && periodEnd(q, k) <= end) inside.push(k);
        expect(stepsInWindow(q, start, end)).toEqual([inside[0], inside[inside.length - 1]]);
      }
    }
  });
});

describe('occupancyClass', () => {
  it('needs the occupancy to exceed a threshold', () => {
    expect(occupancyClass(0, 10, 8)).toBe('empty');
    expect(occupancyClass(10, 10, 8)).toBe('sustained');
    expect(occupancyClass(11, 10, 8)).toBe('peak');
    expect(occupancyClass(8, 10, 8)).toBe('near');
    expect(occupancyClass(6, 10, 8)).toBe('low');
    expect(occupancyClass(7, 10, 8)).toBe('near');
    expect(occupancyClass(3, null, null)).toBe('count');
    expect(occupancyClass(5, 4, null)).toBe('peak');
    expect(occupancyClass(4, 4, null)).toBe('near');
    expect(occupancyClass(3, null, 4)).toBe('low');
    // a sustained threshold above the peak: near is measured against the lower one
    expect(occupancyClass(5, 6, 20)).toBe('near');
  });
});

describe('SparseSeries', () => {
  it('at / maxIn / dense agree with the dense array', () => {
    const rnd = lcg(3);
    const n = 200;
    const dense = Array.from({ length: n }, () => (rnd() < 0.3 ? 1 + Math.floor(rnd() * 20) : 0));
    const idx: number[] = [];
    const cnt: number[] = [];
    dense.forEach((v, k) => v && (idx.push(k), cnt.push(v)));
    const s = SparseSeries.fromWire({ step: idx, count: cnt }, 't');
    expect(Array.from(s.dense(n))).toEqual(dense);
    for (let k = 0; k < n + 3; k++) expect(s.at(k)).toBe(dense[k] ?? 0);
    for (let i = 0; i < 500; i++) {
      const a = Math.floor(rnd() * n);
      const b = a + Math.floor(rnd() * 30);
      expect(s.maxIn(a, b)).toBe(Math.max(0, ...dense.slice(a, b + 1)));
    }
  });
  it('refuses indices out of order and ragged arrays', () => {
    expect(() => SparseSeries.fromWire({ step: [1, 1], count: [1, 2] }, 'x')).toThrow(/ascending/);
    expect(() => SparseSeries.fromWire({ step: [1], count: [] }, 'x')).toThrow(/length/);
  });
});

// A small result: two grid cells stacked over one footprint, one sector-less third cell, two hotspots.
const wire: CongestionResultWire = {
  job: 'j7',
  dataset: 'europe',
  volumes: { grid: {} },
  compute: ['occupancy', 'entries', 'hotspots', 'separation'],
  counts: {
    t0: 1000,
    t1: 1600,
    step: 60,
    duration: 60,
    method: 'interpolated',
    entry_window: 3600,
    entry_step: 1200,
    volumes_kind: 'grid',
    steps: 10,
    entry_windows: 1,
    hours: 1,
    flights: 12,
    volumes: [
      { id: 'r1c1l10', kind: 'cell', south: 45, north: 45.33, west: 5, east: 5.47, lower_m: 9144, upper_m: 10058.4, peak: 3, sustained: 2, max_occupancy: 5, total_entries: 6, occupancy: { step: [0, 3, 4], count: [1, 5, 2] }, entries: { window: [0], count: [6] } },
      { id: 'r1c1l11', kind: 'cell', south: 45, north: 45.33, west: 5, east: 5.47, lower_m: 10058.4, upper_m: 10972.8, peak: 3, sustained: 2, max_occupancy: 3, total_entries: 3, occupancy: { step: [3, 9], count: [3, 1] }, entries: { window: [0], count: [3] } },
      { id: 'r2c9l10', kind: 'cell', south: 45.33, north: 45.67, west: 7, east: 7.47, lower_m: 9144, upper_m: 10058.4, peak: null, sustained: null, max_occupancy: 1, total_entries: 1, occupancy: { step: [5], count: [1] }, entries: { window: [0], count: [1] } },
    ],
    hotspots: [
      { volume: 'r1c1l10', kind: 'peak', first_step: 3, last_step: 3, start: 1180, end: 1240, peak: 5, peak_time: 1180, threshold: 3, excess: 2, flights: [{ id: 4, callsign: 'AFR1', icao24: 'abc' }] },
      { volume: 'r1c1l10', kind: 'sustained', first_step: 3, last_step: 4, start: 1180, end: 1300, peak: 5, peak_time: 1180, threshold: 2, excess: 3, flights: [] },
    ],
    hotspots_total: 2,
    complexity: null,
  },
  separation: { t0: 1000, t1: 1600, flights: 12, count: 1, events: [] },
};

describe('parseResult and the footprint states', () => {
  const m = parseResult(wire);
  it('keeps the periods, the volumes and links hotspots to their volume', () => {
    expect(m.job).toBe('j7');
    expect(m.periods).toEqual({ t0: 1000, t1: 1600, step: 60, duration: 60, steps: 10 });
    expect(m.volumes.map((v) => v.id)).toEqual(['r1c1l10', 'r1c1l11', 'r2c9l10']);
    expect(m.hotspots.map((h) => h.volumeIndex)).toEqual([0, 0]);
    expect(m.volumes[0]!.footprint).toBe(m.volumes[1]!.footprint);
    expect(m.separation).toEqual([]);
  });
  it('shows the worst volume of a footprint at a period and over a window', () => {
    const at3 = footprintStates(m, [3, 3]);
    expect(at3.get(m.volumes[0]!.footprint)).toEqual({ volume: 0, occupancy: 5, cls: 'peak' });
    expect(at3.has(m.volumes[2]!.footprint)).toBe(false);
    const at9 = footprintStates(m, [9, 9]);
    expect(at9.get(m.volumes[0]!.footprint)).toEqual({ volume: 1, occupancy: 1, cls: 'low' });
    const all = footprintStates(m, [0, 9]);
    expect(all.get(m.volumes[2]!.footprint)).toEqual({ volume: 2, occupancy: 1, cls: 'count' });
    expect(footprintStates(m, null).size).toBe(0);
  });
  it('refuses a hotspot of an unknown volume', () => {
    const bad = structuredClone(wire);
    bad.counts!.hotspots[0]!.volume = 'nope';
    expect(() => parseResult(bad)).toThrow(/unknown volume/);
  });
});

describe('rankHotspots', () => {
  const mk = (volume: string, start: number, end: number, excess: number, kind: WireHotspot['kind'] = 'peak'): WireHotspot => ({
    volume,
    kind,
    first_step: 0,
    last_step: 0,
    start,
    end,
    peak: 0,
    peak_time: start,
    threshold: 0,
    excess,
    flights: [],
  });
  const hs = [mk('a', 0, 60, 2), mk('b', 0, 600, 1), mk('c', 60, 120, 2), mk('d', 0, 600, 2), mk('a', 0, 60, 2, 'sustained'), mk('e', 30, 630, 1)];
  it('by excess: larger excess, then longer, then earlier, then volume and kind', () => {
    expect(rankHotspots(hs, 'excess').map((h) => `${h.volume}${h.kind[0]}`)).toEqual(['dp', 'ap', 'as', 'cp', 'bp', 'ep']);
  });
  it('by duration: longer, then larger excess, then earlier', () => {
    expect(rankHotspots(hs, 'duration').map((h) => `${h.volume}${h.kind[0]}`)).toEqual(['dp', 'bp', 'ep', 'ap', 'as', 'cp']);
  });
  it('is a total order consistent with the keys on random input (pairwise check)', () => {
    const rnd = lcg(11);
    const many = Array.from({ length: 300 }, (_, i) => mk(`v${Math.floor(rnd() * 20)}`, Math.floor(rnd() * 10) * 60, 600 + Math.floor(rnd() * 10) * 60, Math.floor(rnd() * 5), i % 2 ? 'peak' : 'sustained'));
    const r = rankHotspots(many, 'excess');
    for (let i = 1; i < r.length; i++) {
      const a = r[i - 1]!;
      const b = r[i]!;
      const key = (x: WireHotspot) => [-x.excess, -(x.end - x.start), x.start];
      const [ka, kb] = [key(a), key(b)];
      const cmp = ka[0]! - kb[0]! || ka[1]! - kb[1]! || ka[2]! - kb[2]!;
      expect(cmp).toBeLessThanOrEqual(0);
    }
    expect(r).toHaveLength(many.length);
  });
});

describe('eventsAt', () => {
  it('lists the events in progress, ends included', () => {
    const ev = (t_start: number, t_end: number) => ({ t_start, t_end }) as SeparationEvent;
    const list = [ev(0, 10), ev(10, 20), ev(30, 40)];
    expect(eventsAt(list, 10)).toEqual([list[0], list[1]]);
    expect(eventsAt(list, 25)).toEqual([]);
  });
});

describe('CSV', () => {
  it('parses quotes, escaped quotes, embedded commas and newlines, CRLF', () => {
    expect(parseCsv('a,b\r\n"x, y","he said ""hi"""\n"multi\nline",\n')).toEqual([
      ['a', 'b'],
      ['x, y', 'he said "hi"'],
      ['multi\nline', ''],
    ]);
    expect(() => parseCsv('"open')).toThrow(/unterminated/);
  });
  it('the series table gives the same sparse series as the JSON', () => {
    // The CSV the server writes for `wire` (counts.hpp write_csv: occupancy rows, then entry rows, per volume).
    const c = wire.counts!;
    const lines = ['volume,series,index,start,end,value'];
    for (const v of c.volumes) {
      v.occupancy.step!.forEach((k, i) => lines.push(`${v.id},occupancy,${k},${c.t0 + k * c.step},${Math.min(c.t0 + k * c.step + c.duration, c.t1)},${v.occupancy.count[i]}`));
      v.entries.window!.forEach((j, i) => lines.push(`${v.id},entries,${j},${c.t0 + j * c.entry_step},${Math.min(c.t0 + j * c.entry_step + c.entry_window, c.t1)},${v.entries.count[i]}`));
    }
    const rows = parseSeriesCsv(lines.join('\n') + '\n');
    expect(rows[1]).toEqual({ volume: 'r1c1l10', series: 'occupancy', index: 3, start: 1180, end: 1240, value: 5 });
    const fromCsv = seriesFromCsv(rows);
    const m = parseResult(wire);
    for (const v of m.volumes) {
      expect(Array.from(fromCsv.get(v.id)!.occupancy.dense(m.periods.steps))).toEqual(Array.from(v.occupancy.dense(m.periods.steps)));
      expect(Array.from(fromCsv.get(v.id)!.entries.dense(1))).toEqual(Array.from(v.entries.dense(1)));
    }
  });
  it('the hotspots table, with quoted sector names and flight ids', () => {
    const text = 'volume,kind,first_step,last_step,start,end,peak,peak_time,threshold,excess,flights\n"EDYY, upper",peak,3,4,1180,1300,5,1180,3,2,4 17 22\nLFFF,sustained,0,0,1000,1060,2,1000,1,1,\n';
    const rows = parseHotspotsCsv(text);
    expect(rows[0]).toEqual({ volume: 'EDYY, upper', kind: 'peak', first_step: 3, last_step: 4, start: 1180, end: 1300, peak: 5, peak_time: 1180, threshold: 3, excess: 2, flights: [4, 17, 22] });
    expect(rows[1]!.flights).toEqual([]);
  });
  it('refuses a wrong header, a ragged row and a non-number', () => {
    expect(() => parseSeriesCsv('vol,series\n')).toThrow(/header/);
    expect(() => parseSeriesCsv('volume,series,index,start,end,value\na,occupancy,1,2,3\n')).toThrow(/5 fields/);
    expect(() => parseSeriesCsv('volume,series,index,start,end,value\na,occupancy,x,2,3,4\n')).toThrow(/index/);
    expect(() => parseSeriesCsv('volume,series,index,start,end,value\na,density,1,2,3,4\n')).toThrow(/unknown series/);
  });
});

describe('map geometry', () => {
  const m = parseResult(wire);
  it('one closed rectangle per grid column', () => {
    const fps = gridFootprints(m.volumes);
    expect(fps.map((f) => f.key)).toEqual([m.volumes[0]!.footprint, m.volumes[2]!.footprint]);
    expect(fps[0]!.ring).toEqual([
      [5, 45],
      [5.47, 45],
      [5.47, 45.33],
      [5, 45.33],
      [5, 45],
    ]);
  });
  it('sector polygons matched by name, rings closed, other features skipped', () => {
    const sec = parseResult({
      ...wire,
      volumes: { sectors: 's1' },
      counts: {
        ...wire.counts!,
        volumes_kind: 'sectors',
        volumes: [{ ...wire.counts!.volumes[0]!, id: 'EDYYUTA', kind: 'sector' }],
        hotspots: [],
      },
    });
    const fc: FeatureCollection = {
      type: 'FeatureCollection',
      features: [
        { type: 'Feature', properties: { name: 'EDYYUTA' }, geometry: { type: 'Polygon', coordinates: [[[5, 45], [6, 45], [6, 46]]] } },
        { type: 'Feature', properties: { name: 'OTHER' }, geometry: { type: 'Polygon', coordinates: [[[0, 0], [1, 0], [1, 1], [0, 0]]] } },
      ],
    };
    expect(sectorFootprints(fc, sec.volumes)).toEqual([{ key: 'sector:EDYYUTA', sector: true, ring: [[5, 45], [6, 45], [6, 46], [5, 45]] }]);
  });
  it('the CPA marker is midway between the aircraft, the short way across 180°', () => {
    const ev = (alon: number, blon: number) => ({ cpa: { a: { lat: 10, lon: alon, alt_m: 0 }, b: { lat: 12, lon: blon, alt_m: 0 } } }) as SeparationEvent;
    expect(cpaPoint(ev(1, 3))).toEqual([2, 11]);
    expect(cpaPoint(ev(179.9, -179.9))).toEqual([-180, 11]);
    expect(cpaPoint(ev(-179.8, 179.9))[0]).toBeCloseTo(-179.95, 9);
  });
});
