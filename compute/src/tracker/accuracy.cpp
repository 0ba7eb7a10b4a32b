// Accuracy of a tracker log against the ground truth it carries (tracker_log.hpp): the acceptance
// figures of the tracker issue. Errors are 3D Euclidean distances between the reported tip
// (TeatEstimate::tip_mm) and the true tip (TeatTruth::tip_mm), in mm, over the (frame, teat) pairs whose
// truth is visible and that the tracker reported visible.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "trailscope/core/error.hpp"
#include "trailscope/tracker/tracker_log.hpp"

namespace trailscope::tracker {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

/// Quantile q of `v` by linear interpolation between closest ranks (numpy's default), so a report can
/// be checked with one numpy call; NaN for an empty set. Sorts `v`.
double quantile(std::vector<double>& v, double q) {
  if (v.empty()) return kNaN;
  std::sort(v.begin(), v.end());
  const double pos = q * static_cast<double>(v.size() - 1);
  const std::size_t lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

double distance(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                   (a[2] - b[2]) * (a[2] - b[2]));
}

/// JSON has no NaN or infinity; nlohmann would write null for both and lose the difference between
/// "no visible teat" and "a visible teat was missed". The tracker log's JSON (protobuf's mapping) writes
/// them as the strings "NaN" and "Infinity", and so does this.
nlohmann::json number(double x) {
  if (std::isnan(x)) return "NaN";
  if (std::isinf(x)) return x > 0 ? "Infinity" : "-Infinity";
  return x;
}

}  // namespace

Accuracy evaluate_accuracy(const TrackerLog& log, double within_mm) {
  if (log.truth.empty())
    throw Error(Error::Kind::unprocessable, "truth", "truth: the log has no ground truth");
  if (log.truth.size() != log.frames.size())
    throw invalid_argument("truth", "truth: " + std::to_string(log.truth.size()) + " entries for " +
                                        std::to_string(log.frames.size()) + " frames");
  if (!std::isfinite(within_mm) || within_mm <= 0)
    throw invalid_argument("within_mm",
                           "within_mm: must be a finite distance > 0 mm, got " + std::to_string(within_mm));
  Accuracy a;
  a.within_mm = within_mm;
  std::vector<double> all;
  std::array<std::vector<double>, tof::kTeatCount> per_teat;
  std::size_t frames_with_visible = 0, frames_within = 0, track_frames = 0;
  a.frame_max_error_mm.assign(log.frames.size(), kNaN);
  for (std::size_t i = 0; i < log.frames.size(); ++i) {
    const FrameLog& f = log.frames[i];
    if (f.state == State::track) ++track_frames;
    if (f.state == State::lost && (i == 0 || log.frames[i - 1].state != State::lost)) ++a.lost_episodes;
    if (!log.truth[i]) continue;
    ++a.frames;
    double worst = kNaN;
    for (int t = 0; t < tof::kTeatCount; ++t) {
      const tof::TeatTruth& truth = log.truth[i]->teats[t];
      if (!truth.visible) continue;
      ++a.teats[t].visible_frames;
      ++a.visible_pairs;
      double e = kInf;  // a visible teat the tracker did not report counts as an infinite miss
      if (f.teats[t].visible) {
        e = distance(f.teats[t].tip_mm, truth.tip_mm);
        ++a.teats[t].reported;
        ++a.reported_pairs;
        per_teat[t].push_back(e);
        all.push_back(e);
      }
      worst = std::isnan(worst) ? e : std::max(worst, e);
    }
    a.frame_max_error_mm[i] = worst;
    if (!std::isnan(worst)) {
      ++frames_with_visible;
      if (worst <= within_mm) ++frames_within;
    }
  }
  double sum = 0;
  for (double e : all) sum += e;
  a.mean_error_mm = all.empty() ? kNaN : sum / static_cast<double>(all.size());
  a.median_error_mm = quantile(all, 0.5);
  a.p95_error_mm = quantile(all, 0.95);
  for (int t = 0; t < tof::kTeatCount; ++t) {
    a.teats[t].median_error_mm = quantile(per_teat[t], 0.5);
    a.teats[t].p95_error_mm = quantile(per_teat[t], 0.95);
  }
  a.frames_all_within = frames_with_visible
                            ? static_cast<double>(frames_within) / static_cast<double>(frames_with_visible)
                            : kNaN;
  a.track_share =
      log.frames.empty() ? 0.0 : static_cast<double>(track_frames) / static_cast<double>(log.frames.size());
  return a;
}

nlohmann::json to_json(const Accuracy& a) {
  nlohmann::json teats = nlohmann::json::array();
  for (int t = 0; t < tof::kTeatCount; ++t)
    teats.push_back({{"name", std::string(tof::kTeatNames[t])},
                     {"visible_frames", a.teats[t].visible_frames},
                     {"reported", a.teats[t].reported},
                     {"median_error_mm", number(a.teats[t].median_error_mm)},
                     {"p95_error_mm", number(a.teats[t].p95_error_mm)}});
  nlohmann::json per_frame = nlohmann::json::array();
  for (double e : a.frame_max_error_mm) per_frame.push_back(number(e));
  return {{"frames", a.frames},
          {"visible_pairs", a.visible_pairs},
          {"reported_pairs", a.reported_pairs},
          {"median_error_mm", number(a.median_error_mm)},
          {"mean_error_mm", number(a.mean_error_mm)},
          {"p95_error_mm", number(a.p95_error_mm)},
          {"frames_all_within", number(a.frames_all_within)},
          {"within_mm", a.within_mm},
          {"track_share", a.track_share},
          {"lost_episodes", a.lost_episodes},
          {"teats", teats},
          {"frame_max_error_mm", per_frame}};
}

}  // namespace trailscope::tracker
