#pragma once
// Reading stored runs' table rows (RunStore::meta) for the analysis routes (importance, projections):
// the runs of a sweep or a list of ids, and the figures of a row.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "routes/app.hpp"
#include "trailscope/analysis/run_table.hpp"

namespace trailscope::server {

/// The figure at dotted `path` ("track_share", "accuracy.median_error_mm") of a run row's summary: the
/// number, NaN when it or its parent is null (no ground truth); nullopt when the path names no number.
std::optional<double> summary_figure(const nlohmann::json& row, const std::string& path);

/// The rows of the runs of `sweep` (404 "sweep" when unknown; empty = no filter) and, when `ids` is not
/// empty, of exactly those ids in that order (404 "run" for an unknown one, 400 "ids" for one twice or
/// one not of the sweep). Store order otherwise. Throws internal when the server has no run store.
std::vector<nlohmann::json> select_runs(App& app, const std::string& sweep,
                                        const std::vector<std::string>& ids);

/// A row's parameters and the analysis::table_metric_names() figures (NaN where null).
analysis::RunFigures run_figures(const nlohmann::json& row);

}  // namespace trailscope::server
