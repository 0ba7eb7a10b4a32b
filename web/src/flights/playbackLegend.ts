// The playback view's colour legend: the animation layer's stops (animation/types.ts `Legend`) as tick
// labels in the dashboard's units (altitude as flight levels, speeds in knots, vertical rates in ft/min,
// callsign prefixes as swatches). Pure functions, unit-tested without a DOM.

import type { ColorBy, Legend } from './animation/types';
import { FT_PER_M, KT_PER_MS, formatInt } from '../lib/format';

export const COLOR_BY_LABELS: Record<ColorBy, string> = {
  altitude: 'Altitude',
  speed: 'Ground speed',
  vrate: 'Vertical rate',
  callsign: 'Callsign prefix',
};

/** A legend value in the units the dashboard shows: "FL350", "450 kt", "+2,000 ft/min", "DLH". */
export function legendLabel(colorBy: ColorBy, value: number | string): string {
  if (typeof value === 'string') return value === '' ? 'other' : value;
  if (!Number.isFinite(value)) return '–';
  switch (colorBy) {
    case 'altitude':
      return `FL${String(Math.max(0, Math.round((value * FT_PER_M) / 100))).padStart(3, '0')}`;
    case 'speed':
      return `${formatInt(value * KT_PER_MS)} kt`;
    case 'vrate': {
      const fpm = Math.round((value * FT_PER_M * 60) / 100) * 100;
      return `${fpm > 0 ? '+' : ''}${formatInt(fpm)} ft/min`;
    }
    default:
      return String(value);
  }
}

export interface LegendTick {
  label: string;
  color: string;
  /** Position along a numeric legend's bar, 0 … 1 (by value); null for a categorical legend. */
  at: number | null;
}

/**
 * The legend's ticks: numeric stops placed along the bar by value (so unevenly spaced stops read right),
 * categorical stops in order.
 */
export function legendTicks(l: Legend): LegendTick[] {
  const numeric = l.stops.length > 0 && l.stops.every((s) => typeof s.value === 'number' && Number.isFinite(s.value));
  if (!numeric) return l.stops.map((s) => ({ label: legendLabel(l.colorBy, s.value), color: s.color, at: null }));
  const vals = l.stops.map((s) => s.value as number);
  const lo = Math.min(...vals);
  const hi = Math.max(...vals);
  return l.stops.map((s) => ({
    label: legendLabel(l.colorBy, s.value),
    color: s.color,
    at: hi > lo ? ((s.value as number) - lo) / (hi - lo) : 0.5,
  }));
}

/** The CSS gradient of a numeric legend (stops at their value's place). */
export function legendGradient(ticks: readonly LegendTick[]): string {
  return `linear-gradient(to right, ${ticks.map((t) => `${t.color} ${((t.at ?? 0) * 100).toFixed(1)}%`).join(', ')})`;
}
