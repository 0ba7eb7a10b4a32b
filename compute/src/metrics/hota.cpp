// HOTA. Two passes as in TrackEval's hota.py: the first accumulates, for every (gt id, tracker id) pair,
// a soft count of co-occurrence that yields a global alignment score; the second matches each frame to
// maximise alignment x similarity and counts TPs per alpha. Pairs are kept sparse (only those that ever
// overlap), so memory follows the overlaps rather than G x T.
#include "trailscope/metrics/hota.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include "trailscope/metrics/assignment.hpp"

namespace trailscope::metrics {
namespace {

constexpr double kEps = DBL_EPSILON;

void finish(HotaResult& r) {
  for (int a = 0; a < kHotaAlphas; ++a) {
    r.det_re[a] = r.tp[a] / std::max(1.0, r.tp[a] + r.fn[a]);
    r.det_pr[a] = r.tp[a] / std::max(1.0, r.tp[a] + r.fp[a]);
    r.det_a[a] = r.tp[a] / std::max(1.0, r.tp[a] + r.fn[a] + r.fp[a]);
    r.hota[a] = std::sqrt(r.det_a[a] * r.ass_a[a]);
    r.rhota[a] = std::sqrt(r.det_re[a] * r.ass_a[a]);
  }
  r.hota0 = r.hota[0];
  r.loc_a0 = r.loc_a[0];
  r.hota_loc_a0 = r.hota0 * r.loc_a0;
}

}  // namespace

double hota_alpha(int a) {
  return 0.05 + a * 0.05;
}

double HotaResult::mean(const HotaCurve& c) {
  return std::accumulate(c.begin(), c.end(), 0.0) / kHotaAlphas;
}

HotaResult hota_metrics(const EvalSequence& seq) {
  HotaResult r;
  if (seq.num_trk_dets == 0 || seq.num_gt_dets == 0) {  // TrackEval's early return
    (seq.num_trk_dets == 0 ? r.fn : r.fp)
        .fill(double(seq.num_trk_dets == 0 ? seq.num_gt_dets : seq.num_trk_dets));
    r.loc_a.fill(1.0);
    r.loc_a0 = 1.0;
    return r;
  }
  const int num_gt = seq.num_gt_ids();
  const auto num_trk = static_cast<std::uint64_t>(seq.num_trk_ids());
  std::vector<double> gt_count(num_gt, 0.0), trk_count(num_trk, 0.0);

  // Pass 1: soft co-occurrence. In a frame, a pair's share is sim / (row sum + column sum - sim): how
  // exclusively the two overlap each other rather than anything else.
  std::unordered_map<std::uint64_t, int> pair_index;
  std::vector<double> potential;                                // per pair
  std::vector<int> gt_of, trk_of;                               // per pair
  std::vector<std::vector<int>> entry_pair(seq.frames.size());  // per frame, per sim entry
  std::vector<double> row_sum, col_sum;
  for (std::size_t t = 0; t < seq.frames.size(); ++t) {
    const EvalFrame& f = seq.frames[t];
    for (const int g : f.gt_ids) gt_count[g] += 1;
    for (const int k : f.trk_ids) trk_count[k] += 1;
    row_sum.assign(f.gt_ids.size(), 0.0), col_sum.assign(f.trk_ids.size(), 0.0);
    for (const auto& s : f.sims) row_sum[s.gt] += s.sim, col_sum[s.trk] += s.sim;
    auto& ep = entry_pair[t];
    ep.reserve(f.sims.size());
    for (const auto& s : f.sims) {
      const int g = f.gt_ids[s.gt], k = f.trk_ids[s.trk];
      const auto [it, fresh] = pair_index.try_emplace(static_cast<std::uint64_t>(g) * num_trk + k,
                                                      static_cast<int>(potential.size()));
      if (fresh) potential.push_back(0.0), gt_of.push_back(g), trk_of.push_back(k);
      ep.push_back(it->second);
      const double denom = row_sum[s.gt] + col_sum[s.trk] - s.sim;
      if (denom > kEps) potential[it->second] += s.sim / denom;
    }
  }
  std::vector<double> alignment(potential.size());
  for (std::size_t p = 0; p < potential.size(); ++p)
    alignment[p] = potential[p] / (gt_count[gt_of[p]] + trk_count[trk_of[p]] - potential[p]);

  // Pass 2: per-frame matching and per-alpha counts.
  std::vector<std::array<int, kHotaAlphas>> matches_count(potential.size(), std::array<int, kHotaAlphas>{});
  HotaCurve loc_sum{};
  HotaCurve alpha{};
  for (int a = 0; a < kHotaAlphas; ++a) alpha[a] = hota_alpha(a);
  std::vector<WeightedPair> pairs;
  std::vector<int> pair_of_match;
  std::vector<double> sim_of_match;
  for (std::size_t t = 0; t < seq.frames.size(); ++t) {
    const EvalFrame& f = seq.frames[t];
    const double ng = double(f.gt_ids.size()), nt = double(f.trk_ids.size());
    if (ng == 0 || nt == 0) {
      for (int a = 0; a < kHotaAlphas; ++a) r.fp[a] += ng == 0 ? nt : 0, r.fn[a] += ng == 0 ? 0 : ng;
      continue;
    }
    pairs.clear();
    for (std::size_t e = 0; e < f.sims.size(); ++e) {
      const double w = alignment[entry_pair[t][e]] * f.sims[e].sim;
      if (w > 0) pairs.push_back({f.sims[e].gt, f.sims[e].trk, w});
    }
    const auto matches = max_weight_matching(static_cast<int>(ng), static_cast<int>(nt), pairs);
    pair_of_match.clear(), sim_of_match.clear();
    for (const auto& [gi, ki] : matches) {
      const auto it = std::lower_bound(f.sims.begin(), f.sims.end(), std::pair{gi, ki},
                                       [](const PairSimilarity& s, const std::pair<int, int>& k) {
                                         return std::pair{s.gt, s.trk} < k;
                                       });
      pair_of_match.push_back(entry_pair[t][it - f.sims.begin()]);
      sim_of_match.push_back(it->sim);
    }
    for (int a = 0; a < kHotaAlphas; ++a) {
      int n = 0;
      for (std::size_t m = 0; m < matches.size(); ++m) {
        if (sim_of_match[m] < alpha[a] - kEps) continue;
        ++n;
        loc_sum[a] += sim_of_match[m];
        ++matches_count[pair_of_match[m]][a];
      }
      r.tp[a] += n, r.fn[a] += ng - n, r.fp[a] += nt - n;
    }
  }

  // Association: each TP is scored by the Jaccard overlap of its two whole tracks.
  for (int a = 0; a < kHotaAlphas; ++a) {
    double ass_a = 0, ass_re = 0, ass_pr = 0;
    for (std::size_t p = 0; p < potential.size(); ++p) {
      const double mc = matches_count[p][a];
      if (mc == 0) continue;
      const double ng = gt_count[gt_of[p]], nt = trk_count[trk_of[p]];
      ass_a += mc * (mc / std::max(1.0, ng + nt - mc));
      ass_re += mc * (mc / std::max(1.0, ng));
      ass_pr += mc * (mc / std::max(1.0, nt));
    }
    const double tp = std::max(1.0, r.tp[a]);
    r.ass_a[a] = ass_a / tp, r.ass_re[a] = ass_re / tp, r.ass_pr[a] = ass_pr / tp;
    r.loc_a[a] = std::max(1e-10, loc_sum[a]) / std::max(1e-10, r.tp[a]);
  }
  finish(r);
  return r;
}

}  // namespace trailscope::metrics
