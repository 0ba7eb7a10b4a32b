// IDF1. TrackEval minimises IDFN + IDFP over a (G+T)^2 matrix with dummy rows/columns; since a matched
// pair (g, t) costs (n_g - c_gt) + (n_t - c_gt) and an unmatched one n_g or n_t, that total is
// GT dets + tracker dets - 2 * sum(c_gt over matched pairs): the same optimum as a maximum-weight
// matching on the overlap counts c_gt, which is sparse and needs no 1e10 sentinels.
#include "trailscope/metrics/identity.hpp"

#include <algorithm>
#include <unordered_map>

#include "trailscope/core/error.hpp"
#include "trailscope/metrics/assignment.hpp"

namespace trailscope::metrics {

IdentityResult identity_metrics(const EvalSequence& seq, double threshold) {
  if (!(threshold > 0 && threshold <= 1)) throw invalid_argument("threshold", "threshold must be in (0, 1]");
  IdentityResult r;
  if (seq.num_trk_dets == 0 || seq.num_gt_dets == 0) {  // TrackEval's early return
    r.idfn = static_cast<long>(seq.num_trk_dets == 0 ? seq.num_gt_dets : 0);
    r.idfp = static_cast<long>(seq.num_trk_dets == 0 ? 0 : seq.num_trk_dets);
    return r;
  }
  const auto num_trk = static_cast<std::uint64_t>(seq.num_trk_ids());
  std::unordered_map<std::uint64_t, long> overlap;  // key g * num_trk + t
  for (const EvalFrame& f : seq.frames)
    for (const auto& s : f.sims)
      // No epsilon here: TrackEval's identity.py compares with a plain >=.
      if (s.sim >= threshold)
        ++overlap[static_cast<std::uint64_t>(f.gt_ids[s.gt]) * num_trk + f.trk_ids[s.trk]];
  std::vector<WeightedPair> pairs;
  pairs.reserve(overlap.size());
  for (const auto& [key, count] : overlap)
    pairs.push_back(
        {static_cast<int>(key / num_trk), static_cast<int>(key % num_trk), static_cast<double>(count)});
  // Deterministic input order, so that ties resolve the same way on every run.
  std::sort(pairs.begin(), pairs.end(), [](const WeightedPair& a, const WeightedPair& b) {
    return std::pair{a.row, a.col} < std::pair{b.row, b.col};
  });
  for (const auto& [g, t] : max_weight_matching(seq.num_gt_ids(), seq.num_trk_ids(), pairs)) {
    const long c = overlap.at(static_cast<std::uint64_t>(g) * num_trk + t);
    r.idtp += c;
    r.pairs.push_back({seq.gt_labels[g], seq.trk_labels[t], c});
  }
  r.idfn = static_cast<long>(seq.num_gt_dets) - r.idtp;
  r.idfp = static_cast<long>(seq.num_trk_dets) - r.idtp;
  r.idr = r.idtp / std::max(1.0, double(r.idtp + r.idfn));
  r.idp = r.idtp / std::max(1.0, double(r.idtp + r.idfp));
  r.idf1 = r.idtp / std::max(1.0, r.idtp + 0.5 * r.idfp + 0.5 * r.idfn);
  return r;
}

}  // namespace trailscope::metrics
