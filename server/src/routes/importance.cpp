// Parameter importance over stored runs: which tracker parameters explain a run-summary metric.
#include <cmath>

#include "routes/handlers.hpp"
#include "routes/run_rows.hpp"
#include "trailscope/analysis/importance.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"

namespace trailscope::server::handlers {

Response importance(App& app, const Request& req, const PathParams&) {
  reject_unknown_params(req, {"metric", "sweep"});
  const auto m = req.query.find("metric");
  if (m == req.query.end() || m->second.empty())
    throw invalid_argument("metric", "metric: required (a run-summary figure, e.g. track_share)");
  const std::string metric = m->second;
  const auto s = req.query.find("sweep");
  const std::string sweep = s == req.query.end() ? "" : s->second;
  std::vector<std::string> names;
  std::vector<double> x, y;
  for (const nlohmann::json& row : select_runs(app, sweep, {})) {
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
