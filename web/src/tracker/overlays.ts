// Draws the tracker's view of one frame over a depth or amplitude image scaled by `s` (image px → canvas
// px): NCC candidates (circles; verified filled-ring yellow, rejected thin grey), each teat's estimate
// (ring + label in the teat's colour; solid when seen this frame, dashed and hollow when only predicted),
// and the ground truth (white crosses at the tips, dashed boxes). Pixel centres are at integer (u, v).

import { TEAT_NAMES, type FrameRecord, type FrameTruth } from '../api/trackerLog';
import { CANDIDATE_REJECTED, CANDIDATE_VERIFIED, TEAT_COLORS, TRUTH_COLOR } from './palette';

export interface OverlayOptions {
  candidates: boolean;
  estimates: boolean;
  truth: boolean;
}

export interface OverlayCounts {
  candidates: number;
  estimates: number;
  truthTips: number;
  truthBoxes: number;
}

const px = (u: number, s: number) => (u + 0.5) * s;

export function drawOverlays(
  ctx: CanvasRenderingContext2D,
  s: number,
  frame: FrameRecord | null,
  truth: FrameTruth | null,
  opts: OverlayOptions,
): OverlayCounts {
  const counts: OverlayCounts = { candidates: 0, estimates: 0, truthTips: 0, truthBoxes: 0 };
  ctx.save();
  ctx.lineJoin = 'round';
  if (opts.truth && truth) {
    ctx.setLineDash([3, 3]);
    ctx.lineWidth = 1;
    truth.teats.forEach((t, i) => {
      if (!t.boxPx) return;
      const [x, y, w, h] = t.boxPx;
      ctx.strokeStyle = withAlpha(TEAT_COLORS[i] ?? TRUTH_COLOR, 0.7);
      ctx.strokeRect(px(x, s), px(y, s), w * s, h * s);
      counts.truthBoxes++;
    });
    ctx.setLineDash([]);
    ctx.lineWidth = 1.5;
    truth.teats.forEach((t, i) => {
      if (!t.tipPx) return;
      const x = px(t.tipPx[0], s);
      const y = px(t.tipPx[1], s);
      const r = 5;
      ctx.strokeStyle = 'rgba(0,0,0,0.7)';
      ctx.lineWidth = 3;
      cross(ctx, x, y, r);
      ctx.strokeStyle = t.visible ? TRUTH_COLOR : 'rgba(255,255,255,0.45)';
      ctx.lineWidth = 1.5;
      cross(ctx, x, y, r);
      if (t.cupAttached) {
        ctx.fillStyle = TEAT_COLORS[i] ?? TRUTH_COLOR;
        ctx.font = '9px ui-monospace, monospace';
        ctx.fillText('cup', x + 6, y + 10);
      }
      counts.truthTips++;
    });
  }
  if (opts.candidates && frame) {
    for (const c of frame.candidates) {
      ctx.beginPath();
      ctx.arc(px(c.u, s), px(c.v, s), c.verified ? 4 : 3, 0, 2 * Math.PI);
      ctx.lineWidth = c.verified ? 1.75 : 1;
      ctx.strokeStyle = c.verified ? CANDIDATE_VERIFIED : CANDIDATE_REJECTED;
      ctx.stroke();
      counts.candidates++;
    }
  }
  if (opts.estimates && frame) {
    ctx.font = '600 11px ui-monospace, monospace';
    frame.teats.forEach((t, i) => {
      if (!t.tracked || !t.tipPx) return;
      const x = px(t.tipPx[0], s);
      const y = px(t.tipPx[1], s);
      const color = TEAT_COLORS[i] ?? '#fff';
      const r = Math.max(7, Math.min(16, 2.2 * s));
      ctx.beginPath();
      ctx.arc(x, y, r, 0, 2 * Math.PI);
      ctx.setLineDash(t.visible ? [] : [3, 3]);
      ctx.lineWidth = t.visible ? 2.25 : 1.5;
      ctx.strokeStyle = color;
      ctx.stroke();
      ctx.setLineDash([]);
      if (t.visible) {
        ctx.beginPath();
        ctx.arc(x, y, 2, 0, 2 * Math.PI);
        ctx.fillStyle = color;
        ctx.fill();
      }
      const label = TEAT_NAMES[i] ?? String(i);
      ctx.lineWidth = 3;
      ctx.strokeStyle = 'rgba(0,0,0,0.75)';
      ctx.strokeText(label, x + r + 2, y - r + 4);
      ctx.fillStyle = color;
      ctx.fillText(label, x + r + 2, y - r + 4);
      counts.estimates++;
    });
  }
  ctx.restore();
  return counts;
}

function cross(ctx: CanvasRenderingContext2D, x: number, y: number, r: number) {
  ctx.beginPath();
  ctx.moveTo(x - r, y - r);
  ctx.lineTo(x + r, y + r);
  ctx.moveTo(x + r, y - r);
  ctx.lineTo(x - r, y + r);
  ctx.stroke();
}

function withAlpha(hex: string, a: number): string {
  const m = /^#([0-9a-f]{6})$/i.exec(hex);
  if (!m) return hex;
  const n = parseInt(m[1]!, 16);
  return `rgba(${(n >> 16) & 255}, ${(n >> 8) & 255}, ${n & 255}, ${a})`;
}
