// Runs as a table of varying parameters and result figures (analysis/run_table.hpp).
#include "trailscope/analysis/run_table.hpp"

#include <cmath>

#include "trailscope/core/error.hpp"

namespace trailscope::analysis {
namespace {

/// Adds `values` (one per run) as column `name` unless it is constant or has a NaN.
void add_column(RunTable& t, std::vector<std::vector<float>>& columns, const std::string& name,
                const std::vector<double>& values) {
  bool constant = true, missing = false;
  for (double v : values) {
    missing = missing || !std::isfinite(v);
    constant = constant && v == values.front();
  }
  if (missing) return t.dropped.push_back({name, "missing in some runs"});
  if (constant) return t.dropped.push_back({name, "constant"});
  t.table.columns.push_back(name);
  columns.emplace_back(values.begin(), values.end());
}

}  // namespace

const std::vector<RunMetric>& run_metrics() {
  static const std::vector<RunMetric> metrics = {{"track_share"},           {"lost_episodes"},
                                                 {"tracker_fps", false},    {"accuracy.median_error_mm"},
                                                 {"accuracy.p95_error_mm"}, {"accuracy.frames_all_within"}};
  return metrics;
}

const std::vector<std::string>& table_metric_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const RunMetric& m : run_metrics())
      if (m.in_table) out.push_back(m.name);
    return out;
  }();
  return names;
}

RunTable run_table(const std::vector<RunFigures>& runs, bool params, bool metrics) {
  if (!params && !metrics) throw invalid_argument("include", "include: name \"params\", \"metrics\" or both");
  if (runs.size() < 2)
    throw Error(Error::Kind::unprocessable, "runs",
                "runs: a projection needs at least 2 runs, got " + std::to_string(runs.size()));
  const RunFigures& first = runs.front();
  for (const RunFigures& r : runs) {
    if (r.param_names != first.param_names || r.params.size() != first.param_names.size())
      throw Error(Error::Kind::unprocessable, "runs",
                  "runs: run " + r.id + " has another parameter vector than run " + first.id +
                      " (another tracker version); choose runs of one version");
    bool same_metrics = r.metrics.size() == first.metrics.size();
    for (std::size_t m = 0; same_metrics && m < r.metrics.size(); ++m)
      same_metrics = r.metrics[m].first == first.metrics[m].first;
    if (!same_metrics)
      throw Error(Error::Kind::unprocessable, "runs",
                  "runs: run " + r.id + " has other metrics than run " + first.id);
  }
  RunTable t;
  std::vector<std::vector<float>> columns;
  std::vector<double> values(runs.size());
  if (params)
    for (std::size_t p = 0; p < first.param_names.size(); ++p) {
      for (std::size_t r = 0; r < runs.size(); ++r) values[r] = runs[r].params[p];
      add_column(t, columns, "param:" + first.param_names[p], values);
    }
  if (metrics)
    for (std::size_t m = 0; m < first.metrics.size(); ++m) {
      for (std::size_t r = 0; r < runs.size(); ++r) values[r] = runs[r].metrics[m].second;
      add_column(t, columns, "metric:" + first.metrics[m].first, values);
    }
  if (columns.empty())
    throw Error(Error::Kind::unprocessable, "runs",
                "runs: every column is constant or missing in some runs; nothing tells these runs apart");
  t.table.rows = runs.size();
  t.table.cols = columns.size();
  t.table.values.resize(t.table.rows * t.table.cols);
  for (std::size_t r = 0; r < t.table.rows; ++r)
    for (std::size_t c = 0; c < t.table.cols; ++c) t.table.values[r * t.table.cols + c] = columns[c][r];
  for (const RunFigures& r : runs) t.row_ids.push_back(r.id);
  projection::validate_table(t.table, "runs");
  return t;
}

}  // namespace trailscope::analysis
