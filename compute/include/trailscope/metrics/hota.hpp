#pragma once
// HOTA, Higher Order Tracking Accuracy (Luiten et al., IJCV 2021), as TrackEval computes it.
#include <array>

#include "trailscope/metrics/sequence.hpp"

namespace trailscope::metrics {

/// Number of localisation thresholds alpha = 0.05, 0.10, ..., 0.95.
inline constexpr int kHotaAlphas = 19;
using HotaCurve = std::array<double, kHotaAlphas>;

/// alpha of index a: 0.05 + 0.05 a, computed as numpy's arange(0.05, 0.99, 0.05) does.
double hota_alpha(int a);

/// Every field is a curve over the 19 alphas; mean() of a curve is TrackEval's summary value
/// ("HOTA___AUC"). All values in [0, 1].
struct HotaResult {
  HotaCurve hota{}, det_a{}, ass_a{}, det_re{}, det_pr{}, ass_re{}, ass_pr{}, loc_a{}, rhota{};
  HotaCurve tp{}, fn{}, fp{};  ///< detection counts (integers stored as double, as TrackEval does)
  double hota0 = 0, loc_a0 = 0,
         hota_loc_a0 = 0;  ///< HOTA(0), LocA(0) = values at the lowest alpha; their product

  static double mean(const HotaCurve& c);
};

/// HOTA with TrackEval's rules: per frame, an optimal assignment maximising
/// global-alignment(gt id, tracker id) x similarity; a pair counts as a true positive at alpha when its
/// similarity >= alpha. As in TrackEval, an empty run or empty ground truth gives all zeros except the
/// FN or FP counts and LocA = LocA(0) = 1.
HotaResult hota_metrics(const EvalSequence& seq);

}  // namespace trailscope::metrics
