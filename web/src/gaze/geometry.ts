// Pure geometry of the stimulus view: which density tiles cover the view at which zoom, how big a fixation's
// circle is, rectangles dragged and polygons clicked on the stimulus, and how many pixels of a layer are
// painted. Stimulus pixels are the world coordinates (origin top-left, y down); the view maps them to CSS
// pixels by a d3-zoom transform (screen = k·p + (x, y)).

import { scaleSqrt } from 'd3-scale';
import type { Aoi, Fixation } from '../api/gazeTypes';

/** The density tiles' size in pixels (the server's). */
export const TILE_PX = 256;
/** The deepest tile zoom the view asks for: 2^6 · 256 px over a 1024-px stimulus is 16 tile pixels per stimulus pixel. */
export const MAX_TILE_Z = 6;

/** The side of the square the tiles cover at zoom 0: the stimulus's longer side. */
export function tileSide(width: number, height: number): number {
  return Math.max(width, height);
}

/**
 * The tile zoom whose tiles are drawn at about one tile pixel per CSS pixel when the view shows `k` CSS
 * pixels per stimulus pixel (the square of side `side` spans 256·2^z tile pixels at zoom z); 0..maxZ.
 */
export function tileZoom(k: number, side: number, maxZ = MAX_TILE_Z): number {
  if (!(k > 0) || !(side > 0)) return 0;
  const z = Math.round(Math.log2((k * side) / TILE_PX));
  return Math.max(0, Math.min(maxZ, z));
}

export interface TileRef {
  z: number;
  x: number;
  y: number;
  /** The tile's square in stimulus pixels: top-left and side. */
  x0: number;
  y0: number;
  size: number;
}

/**
 * The tiles of zoom z that meet the view [vx0, vx1] × [vy0, vy1] (stimulus pixels) inside the stimulus
 * (width × height; tiles wholly outside it are transparent, so not asked for), row by row.
 */
export function visibleTiles(z: number, width: number, height: number, view: { x0: number; y0: number; x1: number; y1: number }): TileRef[] {
  const side = tileSide(width, height);
  const n = 2 ** z;
  const size = side / n;
  const lo = (v: number) => Math.max(0, Math.floor(v / size));
  const hi = (v: number, lim: number) => Math.min(n - 1, Math.ceil(Math.min(v, lim) / size) - 1);
  const out: TileRef[] = [];
  const tx1 = hi(view.x1, width);
  const ty1 = hi(view.y1, height);
  for (let y = lo(view.y0); y <= ty1; y++) for (let x = lo(view.x0); x <= tx1; x++) out.push({ z, x, y, x0: x * size, y0: y * size, size });
  return out;
}

/**
 * A fixation circle's radius in stimulus pixels: area proportional to duration (d3 scaleSqrt), from
 * `rMin` for a zero-length fixation to `rMax` for the longest one of the view (`maxDuration`).
 */
export function fixationRadius(maxDuration: number, rMin = 4, rMax = 28): (durationMs: number) => number {
  const s = scaleSqrt()
    .domain([0, Math.max(1, maxDuration)])
    .range([rMin, rMax])
    .clamp(true);
  return (d) => s(Math.max(0, d));
}

/** The longest fixation of the scanpaths (0 when none). */
export function maxFixationMs(paths: readonly { fixations: readonly Fixation[] }[]): number {
  let m = 0;
  for (const p of paths) for (const f of p.fixations) if (f.duration_ms > m) m = f.duration_ms;
  return m;
}

/** The rectangle [x0, y0, x1, y1] a drag from a to b spans, clipped to the stimulus; null when empty. */
export function dragRect(a: [number, number], b: [number, number], width: number, height: number): [number, number, number, number] | null {
  const cx = (v: number) => Math.max(0, Math.min(width, v));
  const cy = (v: number) => Math.max(0, Math.min(height, v));
  const x0 = cx(Math.min(a[0], b[0]));
  const x1 = cx(Math.max(a[0], b[0]));
  const y0 = cy(Math.min(a[1], b[1]));
  const y1 = cy(Math.max(a[1], b[1]));
  // Hundredths of a pixel, as the URL keeps them.
  const r = (v: number) => Math.round(v * 100) / 100;
  return x1 - x0 >= 1 && y1 - y0 >= 1 ? [r(x0), r(y0), r(x1), r(y1)] : null;
}

/** Whether a click at p closes a polygon (near its first vertex, `tol` stimulus pixels) with at least 3 vertices. */
export function closesPolygon(vertices: readonly [number, number][], p: [number, number], tol: number): boolean {
  if (vertices.length < 3) return false;
  const [x, y] = vertices[0]!;
  return Math.hypot(p[0] - x, p[1] - y) <= tol;
}

/** The SVG path of an AOI (rectangle or polygon) in stimulus pixels. */
export function aoiPath(a: Aoi): string {
  const pts: [number, number][] =
    'rect' in a
      ? [
          [a.rect[0], a.rect[1]],
          [a.rect[2], a.rect[1]],
          [a.rect[2], a.rect[3]],
          [a.rect[0], a.rect[3]],
        ]
      : a.polygon;
  return `M${pts.map(([x, y]) => `${x},${y}`).join('L')}Z`;
}

/** The next free AOI name "AOI n" (n from 1) not in `taken`. */
export function nextAoiName(taken: readonly string[]): string {
  const set = new Set(taken);
  for (let n = 1; ; n++) if (!set.has(`AOI ${n}`)) return `AOI ${n}`;
}

/** How many pixels of RGBA data have a non-zero alpha. */
export function paintedPixels(rgba: Uint8ClampedArray): number {
  let n = 0;
  for (let i = 3; i < rgba.length; i += 4) if (rgba[i] !== 0) n++;
  return n;
}

/** The d3-zoom transform that fits a width × height stimulus centred into a viewW × viewH view (with a margin). */
export function fitTransform(width: number, height: number, viewW: number, viewH: number, margin = 8): { k: number; x: number; y: number } {
  const k = Math.max(1e-6, Math.min((viewW - 2 * margin) / width, (viewH - 2 * margin) / height));
  return { k, x: (viewW - k * width) / 2, y: (viewH - k * height) / 2 };
}

/** The longest time from a scanpath's first fixation start to its last one's (ms; 0 when none). */
export function scanpathSpanMs(paths: readonly { fixations: readonly Fixation[] }[]): number {
  let m = 0;
  for (const p of paths) {
    const n = p.fixations.length;
    if (n > 1) m = Math.max(m, p.fixations[n - 1]!.t_start_ms - p.fixations[0]!.t_start_ms);
  }
  return m;
}
