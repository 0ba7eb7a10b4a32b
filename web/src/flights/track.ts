// A selected flight's track as line segments coloured by altitude (one feature per segment, so the
// colour is data-driven per segment and gaps in altitude stay visible).

import type { Feature, FeatureCollection, LineString, Point } from 'geojson';
import type { ExpressionSpecification } from 'maplibre-gl';
import type { FlightFeature } from '../api/types';
import { ALTITUDE_STOPS_FT } from '../lib/colors';
import { FT_PER_M } from '../lib/format';

export interface TrackData {
  segments: FeatureCollection<LineString>;
  ends: FeatureCollection<Point>;
  /** [west, south, east, north], or null when the flight has no coordinates. */
  bounds: [number, number, number, number] | null;
}

function altitudeAt(f: FlightFeature, i: number): number | null {
  const c = f.geometry.coordinates[i];
  const z = c?.[2];
  if (typeof z === 'number' && Number.isFinite(z)) return z;
  const a = f.properties.altitudes_m?.[i];
  return typeof a === 'number' && Number.isFinite(a) ? a : null;
}

export function trackData(f: FlightFeature): TrackData {
  const coords = f.geometry?.coordinates ?? [];
  const segments: Feature<LineString>[] = [];
  let w = Infinity;
  let s = Infinity;
  let e = -Infinity;
  let n = -Infinity;
  for (let i = 0; i < coords.length; i++) {
    const [lon, lat] = coords[i]!;
    w = Math.min(w, lon);
    e = Math.max(e, lon);
    s = Math.min(s, lat);
    n = Math.max(n, lat);
    if (i === 0) continue;
    const [plon, plat] = coords[i - 1]!;
    const a0 = altitudeAt(f, i - 1);
    const a1 = altitudeAt(f, i);
    const alt = a0 !== null && a1 !== null ? (a0 + a1) / 2 : (a0 ?? a1);
    segments.push({
      type: 'Feature',
      properties: alt === null ? {} : { alt_ft: Math.round(alt * FT_PER_M) },
      geometry: { type: 'LineString', coordinates: [[plon, plat], [lon, lat]] },
    });
  }
  const ends: Feature<Point>[] = [];
  if (coords.length > 0) {
    const first = coords[0]!;
    const last = coords[coords.length - 1]!;
    ends.push({ type: 'Feature', properties: { end: 'start' }, geometry: { type: 'Point', coordinates: [first[0], first[1]] } });
    ends.push({ type: 'Feature', properties: { end: 'end' }, geometry: { type: 'Point', coordinates: [last[0], last[1]] } });
  }
  return {
    segments: { type: 'FeatureCollection', features: segments },
    ends: { type: 'FeatureCollection', features: ends },
    bounds: coords.length > 0 ? [w, s, e, n] : null,
  };
}

/** line-color: altitude ramp by `alt_ft`, grey where the altitude is unknown. */
export function altitudeColorExpression(): ExpressionSpecification {
  const ramp: unknown[] = ['interpolate', ['linear'], ['get', 'alt_ft']];
  for (const [ft, color] of ALTITUDE_STOPS_FT) ramp.push(ft, color);
  return ['case', ['has', 'alt_ft'], ramp, '#8b95a3'] as unknown as ExpressionSpecification;
}
