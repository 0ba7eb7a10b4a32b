// The bundled polylines drawn on a canvas over the map, blended toward the raw trails on the client
// (tsbl.ts), so that the relaxation slider moves without a request. The canvas redraws on every map
// frame; the blend is recomputed only when the relaxation changes.

import type * as maplibregl from 'maplibre-gl';
import { type BlendSource, blendAt, planeToLonLat } from './tsbl';
import { h } from '../lib/dom';

// Faint: thousands of trails overlap, and the bundles' structure shows where they accumulate.
const STROKE = 'rgba(255, 196, 87, 0.14)';

export class BundleOverlay {
  readonly canvas: HTMLCanvasElement;
  private source: BlendSource | null = null;
  private positions: Float64Array | null = null;
  private relaxation = 0;
  private visible = false;
  private frame = 0;

  constructor(private readonly map: maplibregl.Map) {
    this.canvas = h('canvas', { class: 'bundle-overlay', 'data-testid': 'bundle-overlay', 'aria-hidden': 'true' });
    map.getContainer().append(this.canvas);
    map.on('render', () => this.draw());
    map.on('resize', () => this.draw());
  }

  /** The bundle to draw (lon/lat TSBL only: the overlay lives on a map), or null to clear. */
  setSource(s: BlendSource | null): void {
    this.source = s && s.tsbl.lonlat ? s : null;
    this.positions = this.source ? blendAt(this.source, this.relaxation) : null;
    this.canvas.dataset.polylines = String(this.source?.tsbl.n ?? 0);
    this.schedule();
  }

  setRelaxation(r: number): void {
    if (r === this.relaxation) return;
    this.relaxation = r;
    if (this.source) this.positions = blendAt(this.source, r, this.positions ?? undefined);
    this.schedule();
  }

  setVisible(v: boolean): void {
    this.visible = v;
    this.schedule();
  }

  private schedule() {
    cancelAnimationFrame(this.frame);
    this.frame = requestAnimationFrame(() => this.draw());
  }

  private draw() {
    const c = this.canvas;
    const container = this.map.getContainer();
    const dpr = window.devicePixelRatio || 1;
    const w = container.clientWidth, hgt = container.clientHeight;
    if (c.width !== Math.round(w * dpr) || c.height !== Math.round(hgt * dpr)) {
      c.width = Math.round(w * dpr);
      c.height = Math.round(hgt * dpr);
      c.style.width = `${w}px`;
      c.style.height = `${hgt}px`;
    }
    const ctx = c.getContext('2d');
    if (!ctx) return;
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.clearRect(0, 0, c.width, c.height);
    c.dataset.relaxation = this.relaxation.toFixed(2);
    c.dataset.drawn = 'false';
    const s = this.source, pos = this.positions;
    if (!this.visible || !s || !pos) return;
    // The map is never rotated or pitched (both are disabled), so screen position is an affine function of
    // Web Mercator world units: two projected points give it exactly.
    const a = this.map.project(planeToLonLat(0.25, 0.25) as [number, number]);
    const b = this.map.project(planeToLonLat(0.75, 0.75) as [number, number]);
    const sx = ((b.x - a.x) / 0.5) * dpr, sy = ((b.y - a.y) / 0.5) * dpr;
    const ox = a.x * dpr - 0.25 * sx, oy = a.y * dpr - 0.25 * sy;
    ctx.strokeStyle = STROKE;
    ctx.lineWidth = dpr;
    ctx.lineJoin = 'round';
    ctx.beginPath();
    const off = s.tsbl.offsets;
    for (let e = 0; e < s.tsbl.n; e++) {
      const i0 = off[e]!, i1 = off[e + 1]!;
      if (i1 - i0 < 2) continue;
      ctx.moveTo(pos[2 * i0]! * sx + ox, pos[2 * i0 + 1]! * sy + oy);
      for (let i = i0 + 1; i < i1; i++) ctx.lineTo(pos[2 * i]! * sx + ox, pos[2 * i + 1]! * sy + oy);
    }
    ctx.stroke();
    c.dataset.drawn = 'true';
  }
}
