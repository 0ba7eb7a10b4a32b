// The flow layer's model: the streamlines of GET /api/v1/datasets/{dataset}/flow?format=json at two
// levels, and the continuous abstraction level L in [0, 2] moved on the client (van der Zwan, Telea,
// Isenberg, EuroVis 2012): 0 = the density tiles, 1 = the evenly spaced streamlines, 2 = their CUBu bundles.
// Between 0 and 1 the density fades out as the lines fade in; between 1 and 2 each point slides from its
// streamline to its bundle (CUBu's relaxation 2 − L), so the slider needs no request.

/** One line of the route's JSON. */
export interface FlowLine {
  sector: number;
  heading: number | null;
  traffic: number;
  points: [number, number][];
}

export interface FlowJson {
  level: number;
  sectors: number;
  lines: FlowLine[];
  width: number;
  height: number;
}

/** Opacity of the density tiles and of the lines at level L (clamped to [0, 2]). */
export function levelOpacity(level: number): { density: number; lines: number } {
  const l = Math.min(2, Math.max(0, level));
  return { density: Math.max(0, 1 - l), lines: Math.min(1, l) };
}

/**
 * The lines at level L: `streams` (the route's lines just above level 1, resampled like the bundles) for
 * L <= 1, the point-by-point blend toward `bundles` (level 2, the same lines and point counts) above.
 * Throws when the two do not pair up.
 */
export function linesAt(streams: FlowLine[], bundles: FlowLine[], level: number): FlowLine[] {
  if (streams.length !== bundles.length) throw new Error('flow: streamlines and bundles differ in number');
  const t = Math.min(1, Math.max(0, level - 1));
  if (t === 0) return streams;
  return streams.map((s, i) => {
    const b = bundles[i];
    if (b.points.length !== s.points.length) throw new Error(`flow: line ${i} has ${s.points.length} and ${b.points.length} points`);
    return { ...s, points: s.points.map(([x, y], k) => [x + t * (b.points[k][0] - x), y + t * (b.points[k][1] - y)] as [number, number]) };
  });
}

/** The server's line colour: hue = compass heading / 360, saturation 0.85, value 1, as `#rrggbb`. */
export function headingColor(headingDeg: number | null): string {
  if (headingDeg === null || !Number.isFinite(headingDeg)) return '#d9d9d9';
  const h = (((headingDeg / 360) % 1) + 1) % 1;
  const s = 0.85, v = 1;
  const i = Math.floor(h * 6), f = h * 6 - i;
  const p = v * (1 - s), q = v * (1 - f * s), u = v * (1 - (1 - f) * s);
  const [r, g, b] = [[v, u, p], [q, v, p], [p, v, u], [p, q, v], [u, p, v], [v, p, q]][i % 6];
  const hex = (c: number) => Math.round(c * 255).toString(16).padStart(2, '0');
  return `#${hex(r)}${hex(g)}${hex(b)}`;
}

/** Line width in px by traffic, as the server draws it: 1.5 · (0.5 + 1.5 · √(traffic / max)). */
export function lineWidth(traffic: number, maxTraffic: number): number {
  const t = maxTraffic > 0 ? Math.sqrt(Math.min(1, Math.max(0, traffic / maxTraffic))) : 0;
  return 1.5 * (0.5 + 1.5 * t);
}

/** The lines as GeoJSON LineStrings with their colour and width, lightest first (drawn under the main flows). */
export function toFeatures(lines: FlowLine[]): GeoJSON.FeatureCollection<GeoJSON.LineString> {
  const max = lines.reduce((m, l) => Math.max(m, l.traffic), 0);
  const order = lines.map((_, i) => i).sort((a, b) => lines[a].traffic - lines[b].traffic);
  return {
    type: 'FeatureCollection',
    features: order.map((i) => ({
      type: 'Feature',
      properties: { color: headingColor(lines[i].heading), width: lineWidth(lines[i].traffic, max), sector: lines[i].sector },
      geometry: { type: 'LineString', coordinates: lines[i].points },
    })),
  };
}
