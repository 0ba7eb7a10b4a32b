#pragma once
// CLEAR MOT metrics (Bernardin & Stiefelhagen 2008) as TrackEval computes them, plus the per-frame and
// per-target breakdown that the run-comparison views plot (errors over time, lost episodes, jitter).
#include <cstdint>
#include <string>
#include <vector>

#include "trailscope/metrics/sequence.hpp"

namespace trailscope::metrics {

/// One frame under the CLEAR matching.
struct ClearFrame {
  std::int64_t frame = 0;  ///< 1-based
  int gt = 0, trk = 0;     ///< objects present after preprocessing
  int tp = 0, fn = 0, fp = 0, idsw = 0;
  double mean_error = 0;  ///< mean EvalSequence::error_of(sim) over the frame's matches; NaN without any
};

/// One ground-truth object (target) under the CLEAR matching.
struct ClearTarget {
  std::int64_t id = 0;  ///< id in the ground-truth file
  std::int64_t first_frame = 0, last_frame = 0;
  int frames = 0;            ///< frames in which it is present
  int matched = 0;           ///< frames in which a tracker object covers it
  double tracked_ratio = 0;  ///< matched / frames, in [0, 1]
  std::string coverage;      ///< "MT" (> 0.8), "PT" (>= 0.2), "ML"
  int idsw = 0;              ///< identity switches charged to it
  int frag = 0;              ///< times tracking resumed after an interruption
  int lost_episodes = 0;     ///< runs of unmatched presence after the first match
  double mean_error = 0;     ///< over matched frames; NaN if never matched
  double jitter = 0;         ///< mean |error_t - error_{t-1}| over consecutive matched frames; NaN if none
  int jitter_pairs = 0;      ///< number of such frame pairs
};

/// TrackEval's CLEAR fields (same names in to_json). Ratios are in [0, 1] except MOTA, MODA, sMOTA and
/// MOTAL, which can be negative; MOTP is the mean similarity of matches (mean IoU for boxes: higher is
/// better, unlike py-motmetrics' distance MOTP).
struct ClearResult {
  double mota = 0, motp = 0, moda = 0, clr_re = 0, clr_pr = 0, mtr = 0, ptr = 0, mlr = 0, smota = 0;
  double clr_f1 = 0, fp_per_frame = 0, motal = 0, motp_sum = 0;
  long clr_tp = 0, clr_fn = 0, clr_fp = 0, idsw = 0, mt = 0, pt = 0, ml = 0, frag = 0, clr_frames = 0;

  // Extras (not in TrackEval).
  std::vector<ClearFrame> frames;    ///< every frame of the sequence
  std::vector<ClearTarget> targets;  ///< every ground-truth id, in increasing id order
  double mean_error = 0;             ///< over all matches; NaN without any
  double jitter = 0;                 ///< over all targets' consecutive matched frame pairs; NaN if none
  long lost_episodes = 0;            ///< sum over targets
};

/// CLEAR metrics with TrackEval's rules: per frame, an optimal assignment of ground truth to tracker
/// objects with similarity >= `threshold` that first keeps the previous frame's pairs (weight 1000 +
/// sim) and then maximises similarity; an ID switch is a target matched to a tracker id other than the
/// one it was last matched to (any number of frames earlier); MT/PT/ML at > 0.8 / >= 0.2 of frames
/// covered; Frag counts a target's resumptions after frames in which it was not matched. Like TrackEval,
/// the "previous frame" of the continuation rule, of Frag and of the per-target `frag` is the previous
/// frame that had both ground truth and tracker objects (frames with either side empty are skipped), so
/// a gap made only of frames without any tracker object is no fragmentation; lost_episodes counts every
/// gap. As in TrackEval, an empty run or empty ground truth returns only the FN (and ML) or FP
/// counts, every ratio 0 except MLR = 1. Throws Error(invalid_argument, "threshold") unless 0 <
/// threshold <= 1.
ClearResult clear_metrics(const EvalSequence& seq, double threshold = 0.5);

}  // namespace trailscope::metrics
