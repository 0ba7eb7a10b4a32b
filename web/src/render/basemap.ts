// The offline basemap: countries, borders and coastlines from world-atlas (Natural Earth 1:50m),
// converted from TopoJSON in the browser. No tiles, glyphs or sprites are fetched.

import type { StyleSpecification } from 'maplibre-gl';
import type { FeatureCollection, MultiLineString, Feature } from 'geojson';
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
  return {
    land: feature(topo, countries) as FeatureCollection,
    borders: { type: 'Feature', properties: {}, geometry: mesh(topo, countries, (a, b) => a !== b) },
    coast: { type: 'Feature', properties: {}, geometry: mesh(topo, countries, (a, b) => a === b) },
  };
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
