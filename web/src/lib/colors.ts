// Colour ramps: the density colormaps (legend only; the server shades the tiles) and the altitude
// ramp used for a selected flight's track.

import type { Colormap } from '../api/types';

/** Evenly spaced stops approximating the server's colormaps (colorcet fire, matplotlib viridis/inferno/magma, gray). */
export const COLORMAP_STOPS: Record<Colormap, readonly string[]> = {
  fire: ['#000000', '#4a0000', '#9a0600', '#e22a00', '#ff7a00', '#ffc21a', '#fff68a', '#ffffff'],
  viridis: ['#440154', '#482878', '#3e4989', '#31688e', '#26828e', '#1f9e89', '#35b779', '#6ece58', '#b5de2b', '#fde725'],
  inferno: ['#000004', '#1b0c41', '#4a0c6b', '#781c6d', '#a52c60', '#cf4446', '#ed6925', '#fb9b06', '#f7d13d', '#fcffa4'],
  magma: ['#000004', '#180f3d', '#440f76', '#721f81', '#9e2f7f', '#cd4071', '#f1605d', '#fd9668', '#feca8d', '#fcfdbf'],
  gray: ['#000000', '#ffffff'],
};

export function cssGradient(stops: readonly string[], direction = 'to right'): string {
  return `linear-gradient(${direction}, ${stops.join(', ')})`;
}

/** Altitude (feet) → colour stops for the track: green near the ground through cyan and blue to pink at cruise. */
export const ALTITUDE_STOPS_FT: readonly [number, string][] = [
  [0, '#3ddc84'],
  [10000, '#22d3ee'],
  [20000, '#60a5fa'],
  [30000, '#a78bfa'],
  [40000, '#f472b6'],
];
