#pragma once
// The table of a set of tracker runs — one row per run, its varying parameters and its result figures as
// columns — that projections, parallel coordinates and importance read. Columns that cannot tell runs
// apart (constant) or that some run lacks (a figure without ground truth) are dropped and reported.
#include <string>
#include <vector>

#include "trailscope/projection/table.hpp"

namespace trailscope::analysis {

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
