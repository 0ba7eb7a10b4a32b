#pragma once
// The table of a set of tracker runs — one row per run, its varying parameters and its result figures as
// columns — that projections, parallel coordinates and importance read. Columns that cannot tell runs
// apart (constant) or that some run lacks (a figure without ground truth) are dropped and reported.
#include <string>
#include <vector>

#include "trailscope/projection/table.hpp"

namespace trailscope::analysis {

/// A result figure of a tracker run. `name` is also its dotted path into a stored run's summary
/// (server/src/store/run_store.hpp) and its row name in a comparison (run_compare.hpp).
struct RunMetric {
  std::string name;
  bool in_table = true;  ///< a column of run tables (importance, projections); else compared only
};
/// Every result figure of a tracker run, in order: track_share, lost_episodes, tracker_fps (compared
/// only), accuracy.median_error_mm, accuracy.p95_error_mm, accuracy.frames_all_within.
const std::vector<RunMetric>& run_metrics();
/// The names of the run_metrics() that are columns of run tables, in order.
const std::vector<std::string>& table_metric_names();

/// One run's figures. `params` in `param_names` order; `metrics` by name, NaN where the run has none.
struct RunFigures {
  std::string id;
  std::vector<std::string> param_names;
  std::vector<double> params;
  std::vector<std::pair<std::string, double>> metrics;
};

struct DroppedColumn {
  std::string name;
  std::string why;  ///< "constant" or "missing in some runs"
};

struct RunTable {
  projection::Table table;           ///< columns "param:<name>" then "metric:<name>"
  std::vector<std::string> row_ids;  ///< RunFigures::id per row
  std::vector<DroppedColumn> dropped;
};

/// Builds the table of `runs` with their parameters and/or metrics. Every run must have the first run's
/// parameter names and metric names (runs of one tracker version): otherwise Error(unprocessable, "runs")
/// naming the run. Throws Error(invalid_argument, "include") when neither part is asked for, and
/// Error(unprocessable, "runs") for fewer than 2 runs or when no column is left.
RunTable run_table(const std::vector<RunFigures>& runs, bool params, bool metrics);

}  // namespace trailscope::analysis
