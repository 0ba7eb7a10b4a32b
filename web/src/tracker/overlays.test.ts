import { describe, expect, it } from 'vitest';
import { decodeFrameRecord, decodeTruth } from '../api/trackerLog';
import { drawOverlays } from './overlays';

/** A 2D context that records the calls the overlay makes (no canvas in the node test environment). */
function recorder() {
  const calls: { name: string; args: unknown[] }[] = [];
  const ctx = new Proxy({} as Record<string, unknown>, {
    get(target, prop: string) {
      if (prop in target) return target[prop];
      return (...args: unknown[]) => calls.push({ name: prop, args });
    },
    set(target, prop: string, value) {
      target[prop] = value;
      return true;
    },
  });
  return { ctx: ctx as unknown as CanvasRenderingContext2D, calls };
}

const frame = decodeFrameRecord({
  candidates: [
    { u: 10, v: 20, ncc: 0.9, verified: true, teat: 0 },
    { u: 30, v: 40, ncc: 0.6, teat: -1 },
  ],
  teats: [
    { tipPx: [10, 20], tracked: true, visible: true },
    { tipPx: [50, 20], tracked: true, visible: false },
    { tipPx: [0, 0], tracked: false },
    {},
  ],
});
const truth = decodeTruth({
  teats: [
    { name: 'FL', tip_px: [10.2, 20.1], visible: true, box_px: [8.5, 17.5, 4, 6] },
    { name: 'FR', tip_px: null, visible: false, box_px: null },
    { name: 'RL', tip_px: [1, 2], visible: false, box_px: [0.5, 1.5, 2, 2], cup_attached: true },
    { name: 'RR', tip_px: [3, 4], visible: true, box_px: null },
  ],
});

describe('drawOverlays', () => {
  it('draws every candidate, the tracked teats and the truth present, and counts them', () => {
    const { ctx, calls } = recorder();
    const counts = drawOverlays(ctx, 3, frame, truth, { candidates: true, estimates: true, truth: true });
    expect(counts).toEqual({ candidates: 2, estimates: 2, truthTips: 3, truthBoxes: 2 });
    // Image pixel (u, v) has its centre at canvas ((u + 0.5)·s, (v + 0.5)·s).
    const arcs = calls.filter((c) => c.name === 'arc').map((c) => c.args.slice(0, 2));
    expect(arcs).toContainEqual([31.5, 61.5]);
    expect(arcs).toContainEqual([91.5, 121.5]);
    const rects = calls.filter((c) => c.name === 'strokeRect').map((c) => c.args);
    expect(rects[0]).toEqual([27, 54, 12, 18]);
    const labels = calls.filter((c) => c.name === 'fillText').map((c) => c.args[0]);
    expect(labels).toEqual(expect.arrayContaining(['FL', 'FR', 'cup']));
    expect(labels).not.toContain('RL');
  });

  it('draws nothing that is switched off or absent', () => {
    const { ctx } = recorder();
    expect(drawOverlays(ctx, 3, frame, truth, { candidates: false, estimates: false, truth: false })).toEqual({
      candidates: 0,
      estimates: 0,
      truthTips: 0,
      truthBoxes: 0,
    });
    expect(drawOverlays(ctx, 3, null, null, { candidates: true, estimates: true, truth: true }).candidates).toBe(0);
  });
});
