// Geometry of the projection scatter: fitting projected coordinates into a plot with equal scales on both
// axes (distances keep their meaning), and which points a rectangle or lasso brush holds.

export interface Pt {
  x: number;
  y: number;
}

export interface Fit {
  /** plot px = offset + scale · data (y flipped: larger data y is higher up). */
  scale: number;
  ox: number;
  oy: number;
  toPx(x: number, y: number): Pt;
  toData(px: number, py: number): Pt;
}

/** Fits the finite points into width × height with `pad` px margins, one scale for both axes, centred. */
export function fitPoints(points: readonly (readonly [number, number])[], width: number, height: number, pad = 12): Fit {
  let x0 = Infinity;
  let x1 = -Infinity;
  let y0 = Infinity;
  let y1 = -Infinity;
  for (const [x, y] of points) {
    if (!Number.isFinite(x) || !Number.isFinite(y)) continue;
    x0 = Math.min(x0, x);
    x1 = Math.max(x1, x);
    y0 = Math.min(y0, y);
    y1 = Math.max(y1, y);
  }
  if (!Number.isFinite(x0)) {
    x0 = y0 = -1;
    x1 = y1 = 1;
  }
  const w = Math.max(1, width - 2 * pad);
  const hgt = Math.max(1, height - 2 * pad);
  const dx = Math.max(x1 - x0, 1e-12);
  const dy = Math.max(y1 - y0, 1e-12);
  const scale = Math.min(w / dx, hgt / dy);
  const ox = pad + (w - scale * dx) / 2 - scale * x0;
  // Data y up: py = oy − scale·y.
  const oy = pad + (hgt - scale * dy) / 2 + scale * y1;
  return {
    scale,
    ox,
    oy,
    toPx: (x, y) => ({ x: ox + scale * x, y: oy - scale * y }),
    toData: (px, py) => ({ x: (px - ox) / scale, y: (oy - py) / scale }),
  };
}

export interface Rect {
  x0: number;
  y0: number;
  x1: number;
  y1: number;
}

export function normRect(a: Pt, b: Pt): Rect {
  return { x0: Math.min(a.x, b.x), y0: Math.min(a.y, b.y), x1: Math.max(a.x, b.x), y1: Math.max(a.y, b.y) };
}

export function inRect(p: Pt, r: Rect): boolean {
  return p.x >= r.x0 && p.x <= r.x1 && p.y >= r.y0 && p.y <= r.y1;
}

/** Even-odd ray casting; a polygon of fewer than 3 vertices holds nothing. */
export function inPolygon(p: Pt, poly: readonly Pt[]): boolean {
  if (poly.length < 3) return false;
  let inside = false;
  for (let i = 0, j = poly.length - 1; i < poly.length; j = i++) {
    const a = poly[i]!;
    const b = poly[j]!;
    if (a.y > p.y !== b.y > p.y && p.x < ((b.x - a.x) * (p.y - a.y)) / (b.y - a.y) + a.x) inside = !inside;
  }
  return inside;
}

/** Indices of the points (plot px) inside the brush: a rectangle, or a lasso polygon. */
export function brushHits(points: readonly Pt[], brush: { rect: Rect } | { lasso: readonly Pt[] }): number[] {
  const out: number[] = [];
  points.forEach((p, i) => {
    if (!Number.isFinite(p.x) || !Number.isFinite(p.y)) return;
    if ('rect' in brush ? inRect(p, brush.rect) : inPolygon(p, brush.lasso)) out.push(i);
  });
  return out;
}

/** Index of the point nearest to q within `radius` px, or -1. */
export function nearest(points: readonly Pt[], q: Pt, radius: number): number {
  let best = -1;
  let bd = radius * radius;
  points.forEach((p, i) => {
    const d = (p.x - q.x) ** 2 + (p.y - q.y) ** 2;
    if (d <= bd) {
      bd = d;
      best = i;
    }
  });
  return best;
}

/**
 * Points drawn on top of one another: groups of two or more whose pixels lie within `tol` of the group's
 * first point (identical runs project to the same place and would hide each other). Each group lists
 * indices in input order; points with no finite position are left out.
 */
export function overlapGroups(points: readonly Pt[], tol = 1): number[][] {
  const cell = Math.max(tol, 1e-9);
  const grid = new Map<string, number[]>();
  const groups: number[][] = [];
  const owner: number[] = [];
  points.forEach((p, i) => {
    if (!Number.isFinite(p.x) || !Number.isFinite(p.y)) return;
    const cx = Math.floor(p.x / cell);
    const cy = Math.floor(p.y / cell);
    for (let dx = -1; dx <= 1; dx++)
      for (let dy = -1; dy <= 1; dy++) {
        for (const g of grid.get(`${cx + dx},${cy + dy}`) ?? []) {
          const head = points[groups[g]![0]!]!;
          if (Math.hypot(head.x - p.x, head.y - p.y) <= tol) {
            groups[g]!.push(i);
            owner[i] = g;
            return;
          }
        }
      }
    const g = groups.length;
    groups.push([i]);
    owner[i] = g;
    const key = `${cx},${cy}`;
    grid.set(key, [...(grid.get(key) ?? []), g]);
  });
  return groups.filter((g) => g.length > 1);
}
