// Builds EvalSequence from parsed rows: bucketing by frame, MOTChallenge's distractor removal and the
// dense relabelling of ids that the metrics' per-id arrays rely on.
#include "trailscope/metrics/sequence.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/metrics/assignment.hpp"

namespace trailscope::metrics {
namespace {

constexpr double kEps = DBL_EPSILON;  // numpy's finfo('float').eps, which TrackEval's comparisons use

/// Row indices of each frame 1..N (counting sort), with the checks every file gets.
template <typename Row>
std::vector<std::vector<int>> bucket_by_frame(const std::vector<Row>& rows, std::int64_t num_frames,
                                              const std::string& param) {
  std::vector<std::vector<int>> frames(static_cast<std::size_t>(num_frames));
  std::unordered_set<std::int64_t> ids;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const Row& r = rows[k];
    if (r.frame > num_frames)
      throw Error(Error::Kind::unprocessable, param,
                  param + ": line " + std::to_string(r.line) + ": frame " + std::to_string(r.frame) +
                      " is beyond the sequence's " + std::to_string(num_frames) + " frames");
    auto& bucket = frames[r.frame - 1];
    bucket.push_back(static_cast<int>(k));
    if (bucket.size() > limits::kMaxObjectsPerFrame)
      throw Error(Error::Kind::payload_too_large, param,
                  param + ": frame " + std::to_string(r.frame) + " has more than " +
                      std::to_string(limits::kMaxObjectsPerFrame) + " objects");
    if (ids.insert(r.id).second && ids.size() > limits::kMaxTrackIds)
      throw Error(Error::Kind::payload_too_large, param,
                  param + ": more than " + std::to_string(limits::kMaxTrackIds) + " distinct ids");
  }
  // TrackEval refuses an id seen twice in one frame: a track cannot be in two places at once.
  for (auto& bucket : frames) {
    std::sort(bucket.begin(), bucket.end(), [&](int a, int b) { return rows[a].id < rows[b].id; });
    for (std::size_t k = 1; k < bucket.size(); ++k)
      if (rows[bucket[k]].id == rows[bucket[k - 1]].id) {
        const Row& r = rows[std::max(bucket[k], bucket[k - 1])];
        throw Error(Error::Kind::unprocessable, param,
                    param + ": line " + std::to_string(r.line) + ": id " + std::to_string(r.id) +
                        " appears twice in frame " + std::to_string(r.frame));
      }
    std::sort(bucket.begin(), bucket.end());  // back to file order, as TrackEval keeps it
  }
  return frames;
}

template <typename A, typename B>
std::int64_t frame_count(const std::vector<A>& gt, const std::vector<B>& run, std::int64_t num_frames) {
  if (num_frames < 0 || num_frames > limits::kMaxRunFrames)
    throw invalid_argument("frames", "frames must be in 0.." + std::to_string(limits::kMaxRunFrames));
  if (num_frames > 0) return num_frames;
  std::int64_t last = 0;
  for (const auto& r : gt) last = std::max(last, r.frame);
  for (const auto& r : run) last = std::max(last, r.frame);
  return last;
}

/// A frame with file ids; densify() turns these into EvalFrames with dense ids 0..n-1 in increasing
/// file-id order, the order TrackEval's np.unique relabelling gives.
struct RawFrame {
  std::vector<std::int64_t> gt, trk;
  std::vector<PairSimilarity> sims;
};

EvalSequence densify(std::vector<RawFrame>& raw) {
  EvalSequence seq;
  std::vector<std::int64_t> gl, tl;
  for (const auto& f : raw)
    gl.insert(gl.end(), f.gt.begin(), f.gt.end()), tl.insert(tl.end(), f.trk.begin(), f.trk.end());
  seq.num_gt_dets = gl.size();
  seq.num_trk_dets = tl.size();
  const auto unique_sorted = [](std::vector<std::int64_t>& v) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
  };
  unique_sorted(gl), unique_sorted(tl);
  std::unordered_map<std::int64_t, int> gmap, tmap;
  for (std::size_t k = 0; k < gl.size(); ++k) gmap[gl[k]] = static_cast<int>(k);
  for (std::size_t k = 0; k < tl.size(); ++k) tmap[tl[k]] = static_cast<int>(k);
  seq.frames.resize(raw.size());
  for (std::size_t t = 0; t < raw.size(); ++t) {
    EvalFrame& f = seq.frames[t];
    f.frame = static_cast<std::int64_t>(t) + 1;
    for (const auto id : raw[t].gt) f.gt_ids.push_back(gmap.at(id));
    for (const auto id : raw[t].trk) f.trk_ids.push_back(tmap.at(id));
    f.sims = std::move(raw[t].sims);
  }
  seq.gt_labels = std::move(gl);
  seq.trk_labels = std::move(tl);
  return seq;
}

bool is_distractor(int object_class) {
  return object_class == 2 || object_class == 7 || object_class == 8 || object_class == 12;
}

}  // namespace

double box_iou(double ax, double ay, double aw, double ah, double bx, double by, double bw, double bh) {
  // Corner form first, as TrackEval does, so that rounding (and the >= 0.5 decisions) agree bit for bit.
  const double ax1 = ax + aw, ay1 = ay + ah, bx1 = bx + bw, by1 = by + bh;
  const double inter = std::max(std::min(ax1, bx1) - std::max(ax, bx), 0.0) *
                       std::max(std::min(ay1, by1) - std::max(ay, by), 0.0);
  const double area_a = (ax1 - ax) * (ay1 - ay), area_b = (bx1 - bx) * (by1 - by);
  const double uni = area_a + area_b - inter;
  if (area_a <= kEps || area_b <= kEps || uni <= kEps) return 0.0;
  return inter / uni;
}

EvalSequence mot_challenge_sequence(const std::vector<GtBox>& gt, const std::vector<RunBox>& run,
                                    std::int64_t num_frames) {
  const std::int64_t n = frame_count(gt, run, num_frames);
  const auto gt_frames = bucket_by_frame(gt, n, "gt");
  const auto run_frames = bucket_by_frame(run, n, "run");
  const bool has_classes =
      std::any_of(gt.begin(), gt.end(), [](const GtBox& b) { return b.object_class != -1; });

  std::vector<RawFrame> raw(static_cast<std::size_t>(n));
  std::vector<double> iou;
  std::vector<WeightedPair> candidates;
  std::vector<char> removed;
  std::vector<int> kept_gt, kept_trk;
  for (std::int64_t t = 0; t < n; ++t) {
    const auto& gi = gt_frames[t];
    const auto& ri = run_frames[t];
    const int ng = static_cast<int>(gi.size()), nr = static_cast<int>(ri.size());
    iou.assign(static_cast<std::size_t>(ng) * nr, 0.0);
    for (int a = 0; a < ng; ++a) {
      const GtBox& g = gt[gi[a]];
      for (int b = 0; b < nr; ++b) {
        const RunBox& r = run[ri[b]];
        iou[static_cast<std::size_t>(a) * nr + b] = box_iou(g.x, g.y, g.w, g.h, r.x, r.y, r.w, r.h);
      }
    }
    // Step 1: drop tracker boxes that explain a distractor (a person on a bike, a reflection...).
    removed.assign(nr, 0);
    if (has_classes && ng > 0 && nr > 0) {
      candidates.clear();
      for (int a = 0; a < ng; ++a)
        for (int b = 0; b < nr; ++b) {
          const double s = iou[static_cast<std::size_t>(a) * nr + b];
          if (s >= 0.5 - kEps && s > kEps) candidates.push_back({a, b, s});
        }
      for (const auto& [a, b] : max_weight_matching(ng, nr, candidates))
        if (is_distractor(gt[gi[a]].object_class)) removed[b] = 1;
    }
    // Step 2: evaluate pedestrians that are not zero-marked only.
    kept_gt.clear(), kept_trk.clear();
    for (int a = 0; a < ng; ++a) {
      const GtBox& g = gt[gi[a]];
      if (g.consider && (!has_classes || g.object_class == 1)) kept_gt.push_back(a);
    }
    for (int b = 0; b < nr; ++b)
      if (!removed[b]) kept_trk.push_back(b);
    RawFrame& f = raw[t];
    for (const int a : kept_gt) f.gt.push_back(gt[gi[a]].id);
    for (const int b : kept_trk) f.trk.push_back(run[ri[b]].id);
    for (std::size_t x = 0; x < kept_gt.size(); ++x)
      for (std::size_t y = 0; y < kept_trk.size(); ++y) {
        const double s = iou[static_cast<std::size_t>(kept_gt[x]) * nr + kept_trk[y]];
        if (s > 0) f.sims.push_back({static_cast<int>(x), static_cast<int>(y), s});
      }
  }
  EvalSequence seq = densify(raw);
  seq.kind = SimilarityKind::iou;
  return seq;
}

EvalSequence point_sequence(const std::vector<TrackPoint>& gt, const std::vector<TrackPoint>& run,
                            double d_max, std::int64_t num_frames) {
  if (!(d_max > 0) || !std::isfinite(d_max))
    throw invalid_argument("d_max", "d_max must be a positive finite distance");
  const std::int64_t n = frame_count(gt, run, num_frames);
  const auto gt_frames = bucket_by_frame(gt, n, "gt");
  const auto run_frames = bucket_by_frame(run, n, "run");
  std::vector<RawFrame> raw(static_cast<std::size_t>(n));
  for (std::int64_t t = 0; t < n; ++t) {
    RawFrame& f = raw[t];
    for (const int a : gt_frames[t]) f.gt.push_back(gt[a].id);
    for (const int b : run_frames[t]) f.trk.push_back(run[b].id);
    for (std::size_t x = 0; x < gt_frames[t].size(); ++x)
      for (std::size_t y = 0; y < run_frames[t].size(); ++y) {
        const TrackPoint& g = gt[gt_frames[t][x]];
        const TrackPoint& r = run[run_frames[t][y]];
        const double d =
            std::sqrt((g.x - r.x) * (g.x - r.x) + (g.y - r.y) * (g.y - r.y) + (g.z - r.z) * (g.z - r.z));
        const double s = std::max(0.0, 1.0 - d / d_max);
        if (s > 0) f.sims.push_back({static_cast<int>(x), static_cast<int>(y), s});
      }
  }
  EvalSequence seq = densify(raw);
  seq.kind = SimilarityKind::distance;
  seq.d_max = d_max;
  return seq;
}

}  // namespace trailscope::metrics
