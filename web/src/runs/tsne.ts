// The t-SNE perplexity rule of the runs dashboard. The server (compute/src/projection/tsne.cpp) needs
// the 3·perplexity nearest neighbours of every row, i.e. perplexity <= (N − 1) / 3, and perplexity in
// [1, 100]. As openTSNE does (openTSNE.affinity: perplexity lowered to (n − 1) / 3 with a warning), a
// requested perplexity above that is capped and the cap is said; below 4 rows t-SNE is not offered.

/** The largest perplexity the server accepts (limits::kMaxPerplexity). */
export const MAX_PERPLEXITY = 100;
/** The default perplexity (openTSNE's and scikit-learn's). */
export const DEFAULT_PERPLEXITY = 30;

export interface PerplexityChoice {
  /** The perplexity sent, or null when t-SNE cannot run on this many rows. */
  value: number | null;
  /** The requested one was lowered to fit the table. */
  capped: boolean;
  /** Why (shown beside the control). */
  note: string;
}

/** The largest valid perplexity for `rows` rows, rounded down to 0.01 (null below 1). */
export function perplexityCap(rows: number): number | null {
  const cap = Math.min(MAX_PERPLEXITY, Math.floor(((rows - 1) / 3) * 100) / 100);
  return cap >= 1 ? cap : null;
}

/** The perplexity to send for a request of `requested` over `rows` rows. */
export function choosePerplexity(requested: number, rows: number): PerplexityChoice {
  const cap = perplexityCap(rows);
  if (cap === null) return { value: null, capped: false, note: `t-SNE needs at least 4 runs (perplexity ≥ 1 needs 3 neighbours each); this table has ${rows}.` };
  const want = Number.isFinite(requested) ? Math.min(MAX_PERPLEXITY, Math.max(1, requested)) : DEFAULT_PERPLEXITY;
  if (want > cap) return { value: cap, capped: true, note: `perplexity ${want} capped to ${cap} = (N − 1) / 3 for ${rows} runs` };
  return { value: want, capped: false, note: `perplexity ${want} (at most ${cap} for ${rows} runs)` };
}
