// The offline basemap: countries, borders and coastlines from world-atlas (Natural Earth 1:50m),
// converted from TopoJSON in the browser. No tiles, glyphs or sprites are fetched.

import type { StyleSpecification } from 'maplibre-gl';
import type { Feature, FeatureCollection, Geometry, MultiLineString, Position } from 'geojson';
import { feature, mesh } from 'topojson-client';
import type { Topology, GeometryCollection } from 'topojson-specification';

export const BASEMAP_COLORS = {
  water: '#0a0e13',
  land: '#151b23',
  border: '#2b3440',
  coast: '#3b4757',
};

export interface BasemapData {
  land: FeatureCollection;
  borders: Feature<MultiLineString>;
  coast: Feature<MultiLineString>;
}

const EMPTY: FeatureCollection = { type: 'FeatureCollection', features: [] };

/** Loads the bundled world-atlas topology (a separate chunk, so the first paint does not wait on it). */
export async function loadBasemapData(): Promise<BasemapData> {
  const mod = await import('world-atlas/countries-50m.json');
  const topo = (mod.default ?? mod) as unknown as Topology<{ countries: GeometryCollection }>;
  const countries = topo.objects.countries;
  const land = feature(topo, countries) as FeatureCollection;
  for (const f of land.features) if (f.geometry) f.geometry = unwrapPolygons(f.geometry);
  return {
    land,
    borders: { type: 'Feature', properties: {}, geometry: splitAtAntimeridian(mesh(topo, countries, (a, b) => a !== b)) },
    coast: { type: 'Feature', properties: {}, geometry: splitAtAntimeridian(mesh(topo, countries, (a, b) => a === b)) },
  };
}

const crosses = (a: Position, b: Position) => Math.abs(b[0]! - a[0]!) > 180;

/**
 * Rings that cross the antimeridian (Russia's Chukotka, Fiji) jump from +180 to −180, which a
 * renderer draws as a band across the whole world. Shifting their western part by +360° keeps each
 * ring continuous; MapLibre wraps longitudes beyond 180 itself. Polar rings (Antarctica) close
 * along the map's edge and are left alone.
 */
export function unwrapPolygons(g: Geometry): Geometry {
  const fixRing = (ring: Position[]): Position[] => {
    if (!ring.some((p, i) => i > 0 && crosses(ring[i - 1]!, p))) return ring;
    if (ring.some((p) => Math.abs(p[1]!) > 85)) return ring;
    return ring.map((p) => (p[0]! < 0 ? [p[0]! + 360, ...p.slice(1)] : p));
  };
  if (g.type === 'Polygon') return { ...g, coordinates: g.coordinates.map(fixRing) };
  if (g.type === 'MultiPolygon') return { ...g, coordinates: g.coordinates.map((poly) => poly.map(fixRing)) };
  return g;
}

/** Splits lines where they jump across the antimeridian, so no line spans the world. */
export function splitAtAntimeridian(g: MultiLineString): MultiLineString {
  const out: Position[][] = [];
  for (const line of g.coordinates) {
    let part: Position[] = [];
    for (const p of line) {
      if (part.length > 0 && crosses(part[part.length - 1]!, p)) {
        if (part.length > 1) out.push(part);
        part = [];
      }
      part.push(p);
    }
    if (part.length > 1) out.push(part);
  }
  return { type: 'MultiLineString', coordinates: out };
}

/** A dark analyst style with empty basemap sources (filled by loadBasemapData) and the data layers' slots. */
export function basemapStyle(): StyleSpecification {
  return {
    version: 8,
    name: 'TrailScope dark',
    sources: {
      land: { type: 'geojson', data: EMPTY, attribution: 'Natural Earth' },
      borders: { type: 'geojson', data: EMPTY },
      coast: { type: 'geojson', data: EMPTY },
    },
    layers: [
      { id: 'background', type: 'background', paint: { 'background-color': BASEMAP_COLORS.water } },
      { id: 'land', type: 'fill', source: 'land', paint: { 'fill-color': BASEMAP_COLORS.land, 'fill-antialias': false } },
      {
        id: 'borders',
        type: 'line',
        source: 'borders',
        paint: {
          'line-color': BASEMAP_COLORS.border,
          'line-width': ['interpolate', ['linear'], ['zoom'], 2, 0.4, 8, 1.2],
        },
      },
      {
        id: 'coast',
        type: 'line',
        source: 'coast',
        paint: {
          'line-color': BASEMAP_COLORS.coast,
          'line-width': ['interpolate', ['linear'], ['zoom'], 2, 0.5, 8, 1.4],
        },
      },
    ],
  };
}
