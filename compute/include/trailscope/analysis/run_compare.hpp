#pragma once
// Comparison of tracker runs on one video (the runs issue's comparison views): the runs' per-frame series
// aligned on the frames they share, the frames where they disagree most, and their parameter and result
// differences side by side. Runs are compared by frame index (FrameLog::index), so runs over different
// ranges of a video are compared on their overlap.
#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trailscope/tracker/tracker_log.hpp"

namespace trailscope::analysis {

struct CompareOptions {
  /// Disagreements listed, largest first: 1..limits::kMaxCompareTop.
  std::size_t top = 20;
  /// What a teat reported visible by some runs and not by others adds to its spread, mm (> 0), times the
  /// share of runs that miss it: about a teat spacing, so a missed teat weighs like one placed on its
  /// neighbour.
  double miss_mm = 50.0;
  /// Radius of the accuracy figures of the results table, mm (as tracker::evaluate_accuracy).
  double within_mm = 10.0;
};

/// One run's per-frame series over the shared frames.
struct RunSeries {
  std::vector<int> state;  ///< tracker::State as int (0 SEARCH, 1 TRACK, 2 LOST)
  std::vector<int> matches, verified, teats_matched;
  std::vector<double> model_cost, shape_cost;
  /// Largest 3D error over the truth's visible teats, mm: NaN = no truth or no visible teat, +inf = a
  /// visible teat not reported (tracker::Accuracy::frame_max_error_mm). Empty arrays when the log has no
  /// ground truth.
  std::vector<double> max_error_mm;
  /// Per frame and teat (kTeatNames order) the 3D error, mm; NaN where the truth does not show the teat or
  /// the run did not report it. Empty without ground truth.
  std::vector<std::array<double, tof::kTeatCount>> teat_error_mm;
};

/// One frame where the runs disagree.
struct Disagreement {
  std::size_t frame = 0;  ///< frame index in the video
  /// Mean over the four teats of the teat's spread, mm: the largest distance between two runs' estimates
  /// among the runs that report it visible, plus CompareOptions::miss_mm × the share of runs that miss it
  /// when some runs report it and others do not.
  double score_mm = 0;
  std::vector<int> states;  ///< each run's state in this frame
  int worst_teat = 0;       ///< the teat that contributes most (kTeatNames order)
};

/// A parameter, or a result figure, across the runs.
struct ValueRow {
  std::string name;
  std::vector<double> values;  ///< one per run; NaN where a run has no value (e.g. no ground truth)
  bool differs = false;        ///< not every value equal
};

struct Comparison {
  std::string video;
  std::size_t first_frame = 0, frames = 0;  ///< the shared range: indices first_frame .. first_frame+frames-1
  std::vector<RunSeries> series;            ///< one per run, input order
  std::vector<Disagreement> disagreements;  ///< score > 0, largest first (ties: earlier frame first)
  /// Every parameter named by any run's header, differing ones first (then header order); a run whose
  /// header lacks the parameter has NaN.
  std::vector<ValueRow> params;
  /// Run results over the shared frames: track_share, lost_episodes, tracker_fps (from the logged stage
  /// times), and with ground truth accuracy.median_error_mm, accuracy.p95_error_mm,
  /// accuracy.frames_all_within.
  std::vector<ValueRow> results;
};

/// Compares 2..limits::kMaxCompareRuns runs of one video. Throws Error(invalid_argument, "runs") for fewer
/// or more runs, Error(unprocessable, "runs") when they are of different videos, share no frame, or a run's
/// frames are not consecutive; Error(invalid_argument, "top" / "miss_mm" / "within_mm") for options out of
/// range; Error(payload_too_large, "runs") when the shared range exceeds limits::kMaxCompareFrames.
Comparison compare_runs(const std::vector<const tracker::TrackerLog*>& runs,
                        const CompareOptions& options = {});

/// The comparison as the API returns it (proto/openapi.yaml, Comparison): series as arrays, NaN as null and
/// +inf as the string "Infinity" (a missed teat), and the state names.
nlohmann::json to_json(const Comparison& c);

}  // namespace trailscope::analysis
