// CLEAR MOT. The per-frame matching mirrors TrackEval's clear.py so that the counts agree exactly;
// the per-target extras ride along on the same matching so that they agree with the summary.
#include "trailscope/metrics/clear.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>

#include "trailscope/core/error.hpp"
#include "trailscope/metrics/assignment.hpp"

namespace trailscope::metrics {
namespace {

constexpr double kEps = DBL_EPSILON;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// Keeping last frame's pair outweighs any similarity gain (similarities are <= 1).
constexpr double kContinuationBonus = 1000.0;

double similarity_of(const EvalFrame& f, int g, int t) {
  const auto it = std::lower_bound(f.sims.begin(), f.sims.end(), std::pair{g, t},
                                   [](const PairSimilarity& s, const std::pair<int, int>& k) {
                                     return std::pair{s.gt, s.trk} < k;
                                   });
  return it != f.sims.end() && it->gt == g && it->trk == t ? it->sim : 0.0;
}

/// Running state of one target for the extras.
struct TargetState {
  std::int64_t last_match_frame = -1;
  double last_error = 0, error_sum = 0, jitter_sum = 0;
  bool in_lost = false;
};

/// The fields TrackEval derives from the counts (its _compute_final_fields).
void finish(ClearResult& r) {
  const double ids = std::max(1.0, double(r.mt + r.pt + r.ml));
  const double gt = std::max(1.0, double(r.clr_tp + r.clr_fn));
  r.mtr = r.mt / ids, r.ptr = r.pt / ids, r.mlr = r.ml / ids;
  r.clr_re = r.clr_tp / gt;
  r.clr_pr = r.clr_tp / std::max(1.0, double(r.clr_tp + r.clr_fp));
  r.moda = (r.clr_tp - r.clr_fp) / gt;
  r.mota = (r.clr_tp - r.clr_fp - r.idsw) / gt;
  r.motp = r.motp_sum / std::max(1.0, double(r.clr_tp));
  r.smota = (r.motp_sum - r.clr_fp - r.idsw) / gt;
  r.clr_f1 = r.clr_tp / std::max(1.0, r.clr_tp + 0.5 * r.clr_fn + 0.5 * r.clr_fp);
  r.fp_per_frame = r.clr_fp / std::max(1.0, double(r.clr_frames));
  const double log_idsw = r.idsw > 0 ? std::log10(double(r.idsw)) : 0.0;
  r.motal = (r.clr_tp - r.clr_fp - log_idsw) / gt;
}

}  // namespace

ClearResult clear_metrics(const EvalSequence& seq, double threshold) {
  if (!(threshold > 0 && threshold <= 1)) throw invalid_argument("threshold", "threshold must be in (0, 1]");
  ClearResult r;
  const int num_gt = seq.num_gt_ids();
  std::vector<int> present(num_gt, 0), matched_count(num_gt, 0), frag_count(num_gt, 0), idsw_of(num_gt, 0),
      lost_of(num_gt, 0);
  std::vector<std::int64_t> first(num_gt, -1), last(num_gt, -1);
  std::vector<int> jitter_pairs(num_gt, 0);
  std::vector<TargetState> state(num_gt);
  // Last tracker id matched to each target at any time (for IDSW), and in the previous processed frame
  // (for continuing matches and for Frag); -1 = none. TrackEval skips frames without ground truth or
  // without tracker objects entirely, so "previous" means the previous frame that had both.
  std::vector<int> prev_id(num_gt, -1), prev_step_id(num_gt, -1), prev_step_set;
  std::vector<WeightedPair> pairs;
  double error_total = 0, jitter_total = 0;
  long jitter_pairs_total = 0;

  r.frames.reserve(seq.frames.size());
  for (const EvalFrame& f : seq.frames) {
    ClearFrame cf;
    cf.frame = f.frame;
    cf.gt = static_cast<int>(f.gt_ids.size());
    cf.trk = static_cast<int>(f.trk_ids.size());
    cf.mean_error = kNaN;
    for (const int g : f.gt_ids) {
      ++present[g];
      if (first[g] < 0) first[g] = f.frame;
      last[g] = f.frame;
    }
    std::vector<std::pair<int, int>> matches;
    if (cf.gt > 0 && cf.trk > 0) {
      pairs.clear();
      for (const auto& s : f.sims) {
        if (s.sim < threshold - kEps) continue;
        const bool continues = prev_step_id[f.gt_ids[s.gt]] == f.trk_ids[s.trk];
        pairs.push_back({s.gt, s.trk, (continues ? kContinuationBonus : 0.0) + s.sim});
      }
      matches = max_weight_matching(cf.gt, cf.trk, pairs);
      std::vector<char> newly_tracked(matches.size());
      double frame_error = 0;
      for (std::size_t k = 0; k < matches.size(); ++k) {
        const int g = f.gt_ids[matches[k].first], t = f.trk_ids[matches[k].second];
        if (prev_id[g] >= 0 && prev_id[g] != t) ++cf.idsw, ++idsw_of[g];
        newly_tracked[k] = prev_step_id[g] < 0;
        const double sim = similarity_of(f, matches[k].first, matches[k].second);
        r.motp_sum += sim;
        const double err = seq.error_of(sim);
        frame_error += err;
        TargetState& st = state[g];
        if (st.last_match_frame == f.frame - 1) {
          st.jitter_sum += std::fabs(err - st.last_error), ++jitter_pairs[g];
          jitter_total += std::fabs(err - st.last_error), ++jitter_pairs_total;
        }
        st.last_match_frame = f.frame, st.last_error = err, st.error_sum += err, st.in_lost = false;
        ++matched_count[g];
      }
      for (const int g : prev_step_set) prev_step_id[g] = -1;
      prev_step_set.clear();
      for (std::size_t k = 0; k < matches.size(); ++k) {
        const int g = f.gt_ids[matches[k].first], t = f.trk_ids[matches[k].second];
        prev_id[g] = t, prev_step_id[g] = t;
        prev_step_set.push_back(g);
        frag_count[g] += newly_tracked[k];
      }
      cf.tp = static_cast<int>(matches.size());
      error_total += frame_error;
      if (cf.tp > 0) cf.mean_error = frame_error / cf.tp;
    }
    cf.fn = cf.gt - cf.tp;
    cf.fp = cf.trk - cf.tp;
    // Targets present but not covered: a lost episode starts when one that was tracked drops out.
    if (cf.fn > 0) {
      std::vector<char> hit(cf.gt, 0);
      for (const auto& m : matches) hit[m.first] = 1;
      for (int a = 0; a < cf.gt; ++a) {
        TargetState& st = state[f.gt_ids[a]];
        if (!hit[a] && st.last_match_frame >= 0 && !st.in_lost) st.in_lost = true, ++lost_of[f.gt_ids[a]];
      }
    }
    r.clr_tp += cf.tp, r.clr_fn += cf.fn, r.clr_fp += cf.fp, r.idsw += cf.idsw;
    r.frames.push_back(cf);
  }

  r.targets.resize(num_gt);
  for (int g = 0; g < num_gt; ++g) {
    ClearTarget& t = r.targets[g];
    t.id = seq.gt_labels[g];
    t.first_frame = first[g], t.last_frame = last[g];
    t.frames = present[g], t.matched = matched_count[g];
    t.tracked_ratio = present[g] > 0 ? double(matched_count[g]) / present[g] : 0.0;
    t.coverage = t.tracked_ratio > 0.8 ? "MT" : t.tracked_ratio >= 0.2 ? "PT" : "ML";
    t.idsw = idsw_of[g];
    t.frag = std::max(0, frag_count[g] - 1);
    t.lost_episodes = lost_of[g];
    t.mean_error = t.matched > 0 ? state[g].error_sum / t.matched : kNaN;
    t.jitter_pairs = jitter_pairs[g];
    t.jitter = jitter_pairs[g] > 0 ? state[g].jitter_sum / jitter_pairs[g] : kNaN;
    r.mt += t.coverage == "MT", r.pt += t.coverage == "PT";
    r.frag += t.frag;
    r.lost_episodes += t.lost_episodes;
  }
  r.ml = num_gt - r.mt - r.pt;
  r.clr_frames = static_cast<long>(seq.frames.size());
  r.mean_error = r.clr_tp > 0 ? error_total / r.clr_tp : kNaN;
  r.jitter = jitter_pairs_total > 0 ? jitter_total / jitter_pairs_total : kNaN;
  finish(r);

  // TrackEval returns early on an empty side, with only these fields set; match it field for field.
  if (seq.num_trk_dets == 0 || seq.num_gt_dets == 0) {
    ClearResult e;
    e.clr_fn = static_cast<long>(seq.num_trk_dets == 0 ? seq.num_gt_dets : 0);
    e.clr_fp = static_cast<long>(seq.num_trk_dets == 0 ? 0 : seq.num_trk_dets);
    e.ml = seq.num_trk_dets == 0 ? num_gt : 0;
    e.mlr = 1.0;
    e.frames = std::move(r.frames), e.targets = std::move(r.targets);
    e.mean_error = r.mean_error, e.jitter = r.jitter, e.lost_episodes = r.lost_episodes;
    return e;
  }
  return r;
}

}  // namespace trailscope::metrics
