// The aircraft of one instant, on the CPU in float64 (interp.ts): the glyphs the layer draws and what
// positionsAt() reports are the same numbers.

import { bracket, emptyState, stateAt, type FlightState } from './interp';
import { flightPasses, positionPasses, type CompiledFilter } from './filter';
import type { TsanChunk } from './tsan';

/** Aircraft drawn at an instant: flight indices into the chunk and their states (parallel arrays). */
export interface Frame {
  chunk: TsanChunk;
  t: number;
  n: number;
  /** Index of the flight in the chunk. */
  flight: Uint32Array;
  /** Sample a of each (the bracket), reused as the next frame's hint. */
  sample: Int32Array;
  /** x, y relative to the chunk origin (float64 metres). */
  x: Float64Array;
  y: Float64Array;
  lon: Float64Array;
  lat: Float64Array;
  alt: Float32Array;
  speed: Float32Array;
  track: Float32Array;
  vrate: Float32Array;
}

function alloc(chunk: TsanChunk, t: number, cap: number): Frame {
  return {
    chunk, t, n: 0,
    flight: new Uint32Array(cap), sample: new Int32Array(cap),
    x: new Float64Array(cap), y: new Float64Array(cap), lon: new Float64Array(cap), lat: new Float64Array(cap),
    alt: new Float32Array(cap), speed: new Float32Array(cap), track: new Float32Array(cap), vrate: new Float32Array(cap),
  };
}

/**
 * The aircraft of `chunk` (the chunk holding t) at float64 Unix time t that pass `filter`, ordered by
 * flight id. `hints` (per flight of the chunk: the last bracket, or -1) makes playback O(flights) and is
 * updated; `reuse` recycles a previous frame's arrays.
 */
export function frameAt(chunk: TsanChunk, t: number, filter: CompiledFilter, hints?: Int32Array, reuse?: Frame | null): Frame {
  const fr = reuse && reuse.chunk === chunk && reuse.flight.length >= chunk.nFlights ? reuse : alloc(chunk, t, chunk.nFlights);
  fr.t = t;
  const tRel = t - chunk.tStart;
  const st: FlightState = emptyState();
  let n = 0;
  for (let f = 0; f < chunk.nFlights; f++) {
    const a = bracket(chunk, f, tRel, hints ? hints[f]! : -1);
    if (hints) hints[f] = a;
    if (a < 0) continue;
    if (filter.byFlight && !flightPasses(filter, chunk.callsign[f]!, chunk.icao24[f]!)) continue;
    stateAt(chunk, a, t, st);
    if (filter.active && !positionPasses(filter, st.lon, st.lat, st.altM)) continue;
    fr.flight[n] = f;
    fr.sample[n] = a;
    fr.x[n] = st.x;
    fr.y[n] = st.y;
    fr.lon[n] = st.lon;
    fr.lat[n] = st.lat;
    fr.alt[n] = st.altM;
    fr.speed[n] = st.speedMs;
    fr.track[n] = st.trackDeg;
    fr.vrate[n] = st.vrateMs;
    n++;
  }
  fr.n = n;
  return fr;
}
