#include "routes/run_rows.hpp"

#include <limits>
#include <set>

#include "store/run_store.hpp"
#include "store/sweep_store.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::server {

std::optional<double> summary_figure(const nlohmann::json& row, const std::string& path) {
  const nlohmann::json* v = &row.at("summary");
  std::size_t start = 0;
  while (true) {
    if (v->is_null()) return std::numeric_limits<double>::quiet_NaN();
    const std::size_t dot = path.find('.', start);
    const std::string key = path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (!v->is_object() || !v->contains(key)) return std::nullopt;
    v = &(*v)[key];
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  if (v->is_null()) return std::numeric_limits<double>::quiet_NaN();
  if (!v->is_number() || v->is_boolean()) return std::nullopt;
  return v->get<double>();
}

std::vector<nlohmann::json> select_runs(App& app, const std::string& sweep,
                                        const std::vector<std::string>& ids) {
  need(app.runs, "a run store");
  if (!sweep.empty()) {
    need(app.sweeps, "a sweep store");
    app.sweeps->get(sweep);  // 404 "sweep"
  }
  const auto of_sweep = [&](const nlohmann::json& row) {
    return sweep.empty() || row.value("sweep", nlohmann::json()) == sweep;
  };
  std::vector<nlohmann::json> rows;
  if (ids.empty()) {
    for (nlohmann::json& row : app.runs->list())
      if (of_sweep(row)) rows.push_back(std::move(row));
    return rows;
  }
  std::set<std::string> seen;
  for (const std::string& id : ids) {
    if (!seen.insert(id).second) throw invalid_argument("ids", "ids: run '" + id + "' is listed twice");
    nlohmann::json row = app.runs->meta(id);  // 404 "run"
    if (!of_sweep(row))
      throw invalid_argument("ids", "ids: run '" + id + "' is not of sweep '" + sweep + "'");
    rows.push_back(std::move(row));
  }
  return rows;
}

analysis::RunFigures run_figures(const nlohmann::json& row) {
  analysis::RunFigures f;
  f.id = row.at("id").get<std::string>();
  f.param_names = row.at("param_names").get<std::vector<std::string>>();
  f.params = row.at("params").get<std::vector<double>>();
  for (const std::string& m : analysis::table_metric_names())
    f.metrics.emplace_back(m, summary_figure(row, m).value_or(std::numeric_limits<double>::quiet_NaN()));
  return f;
}

}  // namespace trailscope::server
