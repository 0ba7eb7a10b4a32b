#pragma once
// Identity metrics (Ristani et al. 2016: IDF1, IDP, IDR) as TrackEval computes them.
#include <cstdint>
#include <vector>

#include "trailscope/metrics/sequence.hpp"

namespace trailscope::metrics {

/// A ground-truth track and the tracker track the global identity assignment gives it.
struct IdentityPair {
  std::int64_t gt_id = 0;   ///< id in the ground-truth file
  std::int64_t trk_id = 0;  ///< id in the run file
  long idtp = 0;            ///< frames in which the two overlap with similarity >= threshold
};

struct IdentityResult {
  double idf1 = 0, idr = 0, idp = 0;  ///< in [0, 1]
  long idtp = 0, idfn = 0, idfp = 0;
  std::vector<IdentityPair> pairs;  ///< the assignment, pairs with idtp > 0 only, by gt_id
};

/// One global one-to-one assignment of ground-truth to tracker ids that maximises the detections they
/// share (frames with similarity >= `threshold`); IDTP is that maximum, IDFN = GT dets - IDTP, IDFP =
/// tracker dets - IDTP. This equals TrackEval's (G+T)^2 cost formulation, solved on the G x T overlap
/// counts. Throws Error(invalid_argument, "threshold") unless 0 < threshold <= 1.
IdentityResult identity_metrics(const EvalSequence& seq, double threshold = 0.5);

}  // namespace trailscope::metrics
