// Parameter importance over stored runs: which tracker parameters explain a run-summary metric.
#include <cmath>
#include <limits>
#include <optional>

#include "routes/handlers.hpp"
#include "trailscope/analysis/importance.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::server::handlers {

namespace {
nlohmann::json number_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

/// The summary figure at dotted `path` ("track_share", "accuracy.median_error_mm") of a run's row: the
/// number, NaN when it is null or its parent is (no ground truth); nullopt when the path names no number.
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
}  // namespace

Response importance(App& app, const Request& req, const PathParams&) {
  reject_unknown_params(req, {"metric", "sweep"});
  if (!app.runs) throw Error(Error::Kind::internal, "", "this server was started without a run store");
  const auto m = req.query.find("metric");
  if (m == req.query.end() || m->second.empty())
    throw invalid_argument("metric", "metric: required (a run-summary figure, e.g. track_share)");
  const std::string metric = m->second;
  const auto s = req.query.find("sweep");
  std::string sweep;
  if (s != req.query.end()) {
    sweep = s->second;
    if (!app.sweeps) throw Error(Error::Kind::internal, "", "this server was started without a sweep store");
    app.sweeps->get(sweep);  // 404 "sweep"
  }
  std::vector<std::string> names;
  std::vector<double> x, y;
  for (const nlohmann::json& row : app.runs->list()) {
    if (!sweep.empty() && row.value("sweep", nlohmann::json()) != sweep) continue;
    const auto row_names = row.at("param_names").get<std::vector<std::string>>();
    if (names.empty()) names = row_names;
    if (row_names != names)
      throw Error(Error::Kind::unprocessable, "sweep",
                  "run " + row.at("id").get<std::string>() +
                      " has another parameter vector than the first run (another tracker version); choose "
                      "a sweep");
    const auto figure = summary_figure(row, metric);
    if (!figure)
      throw invalid_argument("metric", "metric: '" + metric + "' is not a number of the run summary");
    for (const auto& v : row.at("params")) x.push_back(v.get<double>());
    y.push_back(*figure);
  }
  const analysis::ImportanceResult r = analysis::parameter_importance(x, names, y);
  nlohmann::json inputs = nlohmann::json::array();
  for (const auto& i : r.inputs)
    inputs.push_back({{"name", i.name},
                      {"pearson", number_or_null(i.pearson)},
                      {"spearman", number_or_null(i.spearman)},
                      {"forest", number_or_null(i.forest)}});
  return Response::json(200, {{"metric", metric},
                              {"sweep", sweep.empty() ? nlohmann::json(nullptr) : nlohmann::json(sweep)},
                              {"samples", r.samples},
                              {"forest_r2", number_or_null(r.forest_r2)},
                              {"inputs", std::move(inputs)}});
}

}  // namespace trailscope::server::handlers
