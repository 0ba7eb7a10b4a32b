#pragma once
// The evaluation input every metric reads: per frame, which ground-truth and tracker objects are
// present and how similar each pair is. Building it is where the data-set rules live (MOTChallenge's
// distractor removal, the similarity measure); the metrics themselves never look at boxes or points.
#include <cstdint>
#include <string>
#include <vector>

#include "trailscope/metrics/mot_text.hpp"

namespace trailscope::metrics {

/// Similarity of one ground-truth/tracker pair of a frame; only pairs with sim > 0 are stored.
struct PairSimilarity {
  int gt = 0;      ///< index into EvalFrame::gt_ids
  int trk = 0;     ///< index into EvalFrame::trk_ids
  double sim = 0;  ///< in (0, 1]
};

/// One frame after preprocessing. Ids are dense: 0..num_gt_ids-1 and 0..num_trk_ids-1, unique per frame.
struct EvalFrame {
  std::int64_t frame = 0;  ///< 1-based frame number
  std::vector<int> gt_ids;
  std::vector<int> trk_ids;
  std::vector<PairSimilarity> sims;  ///< sorted by (gt, trk)
};

/// How similarity is measured; decides the meaning of an error.
enum class SimilarityKind {
  iou,       ///< boxes: intersection over union; error = 1 - IoU (dimensionless)
  distance,  ///< points: sim = max(0, 1 - d / d_max); error = d (the points' unit, mm for teats)
};

struct EvalSequence {
  std::vector<EvalFrame> frames;         ///< frames 1..N in order, empty ones included
  std::vector<std::int64_t> gt_labels;   ///< file id of each dense ground-truth id
  std::vector<std::int64_t> trk_labels;  ///< file id of each dense tracker id
  std::size_t num_gt_dets = 0;
  std::size_t num_trk_dets = 0;
  SimilarityKind kind = SimilarityKind::iou;
  double d_max = 0;  ///< distance at which similarity reaches 0 (distance kind only)

  int num_gt_ids() const { return static_cast<int>(gt_labels.size()); }
  int num_trk_ids() const { return static_cast<int>(trk_labels.size()); }
  /// The error of a pair with similarity `sim` > 0: 1 - IoU, or the distance d = (1 - sim) * d_max.
  double error_of(double sim) const { return kind == SimilarityKind::iou ? 1.0 - sim : (1.0 - sim) * d_max; }
};

/// Default d_max for 3D points, millimetres: with the 0.5 match threshold a match needs d <= 10 mm,
/// the sub-centimetre precision an automatic milking robot needs (van der Zwan & Telea, VISAPP 2015).
inline constexpr double kDefaultDistanceMax = 20.0;

/// Intersection over union of two xywh boxes, exactly as TrackEval computes it: 0 when either box has no
/// positive area.
double box_iou(double ax, double ay, double aw, double ah, double bx, double by, double bw, double bh);

/// MOTChallenge preprocessing (TrackEval's mot_challenge_2d_box, pedestrian class), per frame:
///  1. tracker boxes are matched to *all* ground-truth boxes (any class, zero-marked too) by an optimal
///     assignment on IoU, pairs below 0.5 not allowed; tracker boxes matched to a distractor
///     (classes 2 person_on_vehicle, 7 static_person, 8 distractor, 12 reflection) are removed;
///  2. ground truth is reduced to class 1 (pedestrian) with consider = 1.
/// When every ground-truth row has class -1 (MOT15 files), step 1 is skipped and step 2 only drops
/// consider = 0, as TrackEval does for MOT15. Ids are then relabelled densely in increasing order.
/// `num_frames` 0 means the last frame of either file; otherwise rows beyond it are an error.
/// Throws Error(unprocessable, "gt"/"run") naming the line of an id repeated within a frame or of a row
/// beyond `num_frames`, Error(payload_too_large, "gt"/"run") beyond kMaxObjectsPerFrame or kMaxTrackIds,
/// and Error(invalid_argument, "frames") for a negative or too large `num_frames`.
EvalSequence mot_challenge_sequence(const std::vector<GtBox>& gt, const std::vector<RunBox>& run,
                                    std::int64_t num_frames = 0);

/// Ground truth and tracker output as 3D points, similarity max(0, 1 - d / d_max) (d Euclidean).
/// No rows are removed. Throws as mot_challenge_sequence, and Error(invalid_argument, "d_max") unless
/// 0 < d_max < infinity.
EvalSequence point_sequence(const std::vector<TrackPoint>& gt, const std::vector<TrackPoint>& run,
                            double d_max = kDefaultDistanceMax, std::int64_t num_frames = 0);

}  // namespace trailscope::metrics
