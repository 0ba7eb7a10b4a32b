// Small helpers for drawing histograms.

/**
 * Drops the sparse upper tail of a histogram for display: trailing bins that together hold less than
 * `fraction` of the total (outliers such as a bogus FL990 would otherwise squash the chart).
 * Returns how many bins are kept and how many samples the dropped tail held.
 */
export function trimTail(counts: readonly number[], fraction = 0.001): { keep: number; hidden: number } {
  const total = counts.reduce((a, b) => a + b, 0);
  let keep = counts.length;
  let tail = 0;
  while (keep > 1) {
    const c = counts[keep - 1]!;
    if (tail + c > total * fraction) break;
    tail += c;
    keep--;
  }
  return { keep, hidden: tail };
}
