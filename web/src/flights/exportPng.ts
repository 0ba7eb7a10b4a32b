// "Export PNG": the map as it is on screen (basemap, density or bundle tiles, track, aircraft) with its
// legend and a caption naming the data set and window, as one PNG the analyst can paste into a report.
// The map's WebGL canvas keeps no drawing buffer, so it is copied inside MapLibre's own 'render' event,
// while the frame just drawn is still there.

import type * as maplibregl from 'maplibre-gl';
import type { LegendSpec } from '../lib/legend';

/** The legend box's geometry in CSS pixels (drawLegend). */
const BOX = { pad: 8, title: 14, bar: 10, ticks: 18, note: 13 };

/** Copies the map's next rendered frame into a 2D canvas of the same pixel size. */
function captureMap(map: maplibregl.Map): Promise<HTMLCanvasElement> {
  return new Promise((resolve) => {
    map.once('render', () => {
      const src = map.getCanvas();
      const out = document.createElement('canvas');
      out.width = src.width;
      out.height = src.height;
      out.getContext('2d')!.drawImage(src, 0, 0);
      resolve(out);
    });
    map.triggerRepaint();
  });
}

/** Draws a legend (the same spec the on-screen legend is drawn from) with its box's top-left at (x, y), CSS px × scale. */
export function drawLegend(ctx: CanvasRenderingContext2D, spec: LegendSpec, x: number, y: number, scale: number): { w: number; h: number } {
  const W = spec.width;
  const h = BOX.pad * 2 + BOX.title + BOX.bar + BOX.ticks + (spec.note ? BOX.note : 0);
  ctx.save();
  ctx.font = '10px sans-serif';
  const noteW = spec.note ? ctx.measureText(spec.note).width : 0;
  ctx.font = '11px sans-serif';
  const w = Math.max(W + 24, noteW, ctx.measureText(spec.title).width) + BOX.pad * 2;
  ctx.scale(scale, scale);
  ctx.translate(x / scale, y / scale);
  ctx.fillStyle = 'rgba(17, 22, 29, 0.88)';
  ctx.fillRect(0, 0, w, h);
  ctx.fillStyle = '#e5e7eb';
  ctx.font = '11px sans-serif';
  ctx.textBaseline = 'top';
  ctx.fillText(spec.title, BOX.pad, BOX.pad);
  const bx = BOX.pad + 12;
  const by = BOX.pad + BOX.title;
  const g = ctx.createLinearGradient(bx, 0, bx + W, 0);
  spec.stops.forEach((c, i) => g.addColorStop(spec.stops.length > 1 ? i / (spec.stops.length - 1) : 0, c));
  ctx.fillStyle = g;
  ctx.fillRect(bx, by, W, BOX.bar);
  ctx.strokeStyle = '#9ca3af';
  ctx.fillStyle = '#9ca3af';
  ctx.font = '9.5px monospace';
  ctx.textAlign = 'center';
  for (const t of spec.ticks) {
    const tx = bx + t.at * W;
    ctx.beginPath();
    ctx.moveTo(tx + 0.5, by + BOX.bar);
    ctx.lineTo(tx + 0.5, by + BOX.bar + 4);
    ctx.stroke();
    ctx.fillText(t.label, tx, by + BOX.bar + 5);
  }
  if (spec.note) {
    ctx.textAlign = 'left';
    ctx.font = '10px sans-serif';
    ctx.fillText(spec.note, BOX.pad, by + BOX.bar + BOX.ticks);
  }
  ctx.restore();
  return { w: w * scale, h: h * scale };
}

/** The map view as a PNG with `legend` (bottom-left, as on screen) and `caption` (top-left). */
export async function mapPng(map: maplibregl.Map, legend: LegendSpec | null, caption: string): Promise<Blob> {
  const canvas = await captureMap(map);
  const ctx = canvas.getContext('2d')!;
  const scale = canvas.width / Math.max(1, map.getCanvas().clientWidth);
  ctx.save();
  ctx.scale(scale, scale);
  ctx.font = '12px sans-serif';
  ctx.textBaseline = 'top';
  const cw = ctx.measureText(caption).width;
  ctx.fillStyle = 'rgba(17, 22, 29, 0.88)';
  ctx.fillRect(6, 6, cw + 12, 20);
  ctx.fillStyle = '#e5e7eb';
  ctx.fillText(caption, 12, 10);
  ctx.restore();
  if (legend) {
    const hCss = BOX.pad * 2 + BOX.title + BOX.bar + BOX.ticks + (legend.note ? BOX.note : 0);
    drawLegend(ctx, legend, 10 * scale, canvas.height - (hCss + 30) * scale, scale);
  }
  return new Promise((resolve, reject) => canvas.toBlob((b) => (b ? resolve(b) : reject(new Error('PNG encoding failed'))), 'image/png'));
}

/** Saves a blob as a file through a temporary link (the browser's download). */
export function download(blob: Blob, name: string): void {
  const url = URL.createObjectURL(blob);
  const a = document.createElement('a');
  a.href = url;
  a.download = name;
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10_000);
}
