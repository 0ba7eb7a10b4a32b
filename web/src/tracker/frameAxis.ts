// Frame index ⇄ horizontal position on the frame-axis views (state timeline, trajectories).
// Frame i covers [i·w/n, (i+1)·w/n) of a plot of width w showing n frames.

export function frameAt(x: number, width: number, frames: number): number {
  if (frames <= 0 || width <= 0) return 0;
  const i = Math.floor((x / width) * frames);
  return Math.max(0, Math.min(frames - 1, i));
}

/** Centre of frame i. */
export function xOfFrame(i: number, width: number, frames: number): number {
  if (frames <= 0) return 0;
  return ((i + 0.5) * width) / frames;
}

/** Left edge of frame i. */
export function frameLeft(i: number, width: number, frames: number): number {
  if (frames <= 0) return 0;
  return (i * width) / frames;
}

/** "Nice" tick step (1, 2, 5 × 10^k frames) giving at most `maxTicks` ticks over `frames`. */
export function tickStep(frames: number, maxTicks: number): number {
  const raw = Math.max(1, frames / Math.max(1, maxTicks));
  const p = 10 ** Math.floor(Math.log10(raw));
  for (const m of [1, 2, 5, 10]) if (m * p >= raw) return m * p;
  return 10 * p;
}
