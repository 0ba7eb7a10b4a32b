#pragma once
// One call from two text files to every metric, and the two ways of showing the result: TrackEval's
// column names and tables (so numbers can be checked against TrackEval output side by side) and JSON.
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "trailscope/metrics/clear.hpp"
#include "trailscope/metrics/hota.hpp"
#include "trailscope/metrics/identity.hpp"
#include "trailscope/metrics/sequence.hpp"

namespace trailscope::metrics {

struct MetricsOptions {
  SimilarityKind kind = SimilarityKind::iou;  ///< iou: MOTChallenge box files; distance: 3D point files
  double d_max = kDefaultDistanceMax;         ///< distance kind only, in the points' unit (mm)
  std::int64_t frames = 0;                    ///< sequence length; 0 = last frame of either file
};

struct MetricsReport {
  SimilarityKind kind = SimilarityKind::iou;
  double d_max = 0;
  HotaResult hota;
  ClearResult clear;
  IdentityResult identity;
  long dets = 0, gt_dets = 0, ids = 0, gt_ids = 0;  ///< TrackEval's "Count" fields, after preprocessing
  double ms = 0;  ///< wall time of evaluate_text / evaluate (parsing included for evaluate_text)
};

/// Every metric of one preprocessed sequence.
MetricsReport evaluate(const EvalSequence& seq);

/// Parses, preprocesses (mot_challenge_sequence or point_sequence) and evaluates. Throws what those
/// throw: Error(unprocessable | payload_too_large, "gt" / "run") for bad files, Error(invalid_argument,
/// "d_max" / "frames") for bad options.
MetricsReport evaluate_text(std::string_view gt_text, std::string_view run_text,
                            const MetricsOptions& options);

/// The report as (TrackEval column name, value) in the order of TrackEval's pedestrian_detailed.csv:
/// HOTA(0), LocA(0), HOTALocA(0), then HOTA___5 ... HOTA___95, HOTA___AUC (mean) for each HOTA curve,
/// then the CLEAR, Identity and Count fields. Ratios are fractions (0.65188), not percentages.
std::vector<std::pair<std::string, double>> trackeval_columns(const MetricsReport& report);

/// JSON: {"similarity", "d_max"?, "ms", "metrics": {TrackEval columns}, "extras": {mean_error, jitter,
/// lost_episodes, error_unit}, and with `details` also "per_frame", "per_target", "identity_pairs"}.
/// NaN values (no matches) are written as null.
nlohmann::json to_json(const MetricsReport& report, bool details);

/// TrackEval-style text tables (HOTA, CLEAR, Identity, Count; percentages with 3 decimals) for one
/// sequence named `name`, followed by the extras.
std::string to_table(const MetricsReport& report, const std::string& name);

}  // namespace trailscope::metrics
