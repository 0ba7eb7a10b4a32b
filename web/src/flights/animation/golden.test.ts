// The server's own chunk (tests/golden/anim_boundaries.tsan, written by the server test from its encoder)
// against the server's positions_at() at seven instants (tests/golden/anim_boundaries.json): the decoder
// and the client interpolation must give the same flights and positions, to the metre.
import { readFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import path from 'node:path';
import { describe, expect, it } from 'vitest';
import { decodeTsan, icaoText } from './tsan';
import { frameAt } from './frame';
import { compileFilter } from './filter';

const golden = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../../../../tests/golden');

interface Pos { id: number; lat: number; lon: number; alt_m: number | null; callsign: string; icao24: string; exact: boolean }

describe('the server chunk tests/golden/anim_boundaries.tsan', () => {
  const buf = readFileSync(path.join(golden, 'anim_boundaries.tsan'));
  const chunk = decodeTsan(buf.buffer.slice(buf.byteOffset, buf.byteOffset + buf.byteLength));
  const ref = JSON.parse(readFileSync(path.join(golden, 'anim_boundaries.json'), 'utf8')) as {
    chunk: { t: number; duration: number };
    instants: Array<{ t: number; positions: Pos[] }>;
  };

  it('decodes the chunk the server says it is', () => {
    expect(chunk.tStart).toBe(ref.chunk.t);
    expect(chunk.duration).toBe(ref.chunk.duration);
    expect(chunk.nFlights).toBeGreaterThan(0);
  });

  for (const inst of ref.instants) {
    it(`positions at t = ${inst.t} equal the server's positions_at()`, () => {
      const fr = frameAt(chunk, inst.t, compileFilter({}));
      expect(fr.n).toBe(inst.positions.length);
      for (let i = 0; i < fr.n; i++) {
        const p = inst.positions[i]!, f = fr.flight[i]!;
        expect(chunk.flightId[f]).toBe(p.id);
        expect(chunk.callsign[f]).toBe(p.callsign);
        expect(icaoText(chunk.icao24[f]!)).toBe(p.icao24);
        const k = (6371008.8 * Math.PI) / 180;
        const dx = (fr.lon[i]! - p.lon) * k * Math.cos((p.lat * Math.PI) / 180), dy = (fr.lat[i]! - p.lat) * k;
        expect(Math.hypot(dx, dy)).toBeLessThan(1);
        if (p.alt_m === null) expect(Number.isNaN(fr.alt[i]!)).toBe(true);
        else expect(fr.alt[i]!).toBeCloseTo(p.alt_m, 2);
      }
    });
  }
});
