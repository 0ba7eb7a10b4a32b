import { describe, expect, it } from 'vitest';

import { callsignMatches, compileFilter, flightPasses } from './filter';
import { TSAN_NO_ICAO } from './tsan';

/** An independent matcher: the pattern as a regular expression (`*` → `.*`, `?` → `.`), prefix without wildcards. */
function byRegExp(pattern: string, callsign: string): boolean {
  if (!/[*?]/.test(pattern)) return callsign.startsWith(pattern);
  const re = new RegExp('^' + pattern.replace(/\*/g, '.*').replace(/\?/g, '.') + '$');
  return re.test(callsign);
}

describe('callsign patterns (the API rule)', () => {
  it('matches the server test cases (tests/compute/trails/query_test.cpp CallsignMatch)', () => {
    expect(callsignMatches('KLM', 'KLM1234')).toBe(true);
    expect(callsignMatches('KLM', 'AKLM')).toBe(false);
    expect(callsignMatches('KLM*4', 'KLM1234')).toBe(true);
    expect(callsignMatches('KLM*5', 'KLM1234')).toBe(false);
    expect(callsignMatches('?LM12??', 'KLM1234')).toBe(true);
    expect(callsignMatches('?LM12?', 'KLM1234')).toBe(false);
    expect(callsignMatches('*', '')).toBe(true);
    expect(callsignMatches('*A*B*', 'XAYBZ')).toBe(true);
  });

  it('agrees with a regular-expression matcher on random patterns and callsigns', () => {
    let seed = 7;
    const rnd = () => ((seed = (seed * 1103515245 + 12345) >>> 0) / 2 ** 32);
    const pick = (s: string) => s[Math.floor(rnd() * s.length)]!;
    for (let i = 0; i < 5000; i++) {
      const cs = Array.from({ length: Math.floor(rnd() * 8) }, () => pick('AB12')).join('');
      const pat = Array.from({ length: 1 + Math.floor(rnd() * 6) }, () => pick('AB12*?')).join('');
      expect(callsignMatches(pat, cs), `${pat} ~ ${cs}`).toBe(byRegExp(pat, cs));
    }
  });

  it('flight tests: pattern case-insensitive, icao24 list, unknown address fails a list', () => {
    const f = compileFilter({ callsign: 'dlh*9', icao24: ['3C6589', 'abc123'] });
    expect(f.byFlight).toBe(true);
    expect(flightPasses(f, 'DLH4A9', 0x3c6589)).toBe(true);
    expect(flightPasses(f, 'DLH4A8', 0x3c6589)).toBe(false);
    expect(flightPasses(f, 'DLH4A9', 0x3c658a)).toBe(false);
    expect(flightPasses(f, 'DLH4A9', TSAN_NO_ICAO)).toBe(false);
    expect(flightPasses(compileFilter({ callsign: 'DLH' }), '', 1)).toBe(false);
    expect(compileFilter({}).byFlight).toBe(false);
  });
});
