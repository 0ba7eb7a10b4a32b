// Colours of the tracker views: one per teat (FL FR RL RR) and one per model state, as in the paper's
// model-state view (blue = tracking, red = lost; grey = searching).

import type { TrackerState } from '../api/trackerLog';

export const TEAT_COLORS = ['#ff8a1f', '#22d3ee', '#a3e635', '#f472b6'] as const;

export const STATE_COLORS: Record<TrackerState, string> = {
  TRACK: '#3b82f6',
  LOST: '#ef4444',
  SEARCH: '#6b7685',
};
/** Frames not computed yet. */
export const UNKNOWN_COLOR = '#161c24';

export const CANDIDATE_VERIFIED = '#fde047';
export const CANDIDATE_REJECTED = 'rgba(215, 221, 229, 0.55)';
export const TRUTH_COLOR = '#ffffff';
