// POST /api/v1/projections: a 2D projection (compute/projection) of an inline table or of stored runs
// (their varying parameters and result figures), with its quality.
#include "routes/handlers.hpp"
#include "routes/run_rows.hpp"
#include "params/json_fields.hpp"
#include "trailscope/core/error.hpp"
#include "limits.hpp"
#include "trailscope/projection/report.hpp"

namespace trailscope::server::handlers {
namespace {

/// {"columns": [names], "rows": [[numbers]]} → Table; every error names "table" and the row.
projection::Table inline_table(const nlohmann::json& j) {
  if (!j.is_object() || !j.contains("rows") || !j["rows"].is_array())
    throw invalid_argument("table", "table: must be an object {\"columns\": [names], \"rows\": [[numbers]]}");
  const nlohmann::json& rows = j["rows"];
  projection::Table t;
  t.rows = rows.size();
  t.cols = t.rows > 0 && rows[0].is_array() ? rows[0].size() : 0;
  if (t.rows > limits::kMaxProjectionRequestRows)
    throw Error(Error::Kind::payload_too_large, "table",
                "table: " + std::to_string(t.rows) + " rows, at most " +
                    std::to_string(limits::kMaxProjectionRequestRows) + " in a request");
  if (t.rows * t.cols > limits::kMaxProjectionRequestCells)
    throw Error(Error::Kind::payload_too_large, "table",
                "table: " + std::to_string(t.rows * t.cols) + " cells, at most " +
                    std::to_string(limits::kMaxProjectionRequestCells) + " in a request");
  if (j.contains("columns")) {
    if (!j["columns"].is_array() || j["columns"].size() != t.cols)
      throw invalid_argument("table", "table: columns must list " + std::to_string(t.cols) + " names");
    for (const auto& c : j["columns"]) {
      if (!c.is_string()) throw invalid_argument("table", "table: column names must be strings");
      t.columns.push_back(c.get<std::string>());
    }
  }
  t.values.reserve(t.rows * t.cols);
  for (std::size_t r = 0; r < t.rows; ++r) {
    const std::string where = "table: row " + std::to_string(r + 1);
    if (!rows[r].is_array() || rows[r].size() != t.cols)
      throw invalid_argument("table", where + " must be an array of " + std::to_string(t.cols) + " numbers");
    for (const auto& v : rows[r]) {
      if (!v.is_number()) throw invalid_argument("table", where + " has a value that is not a number");
      t.values.push_back(v.get<float>());
    }
  }
  projection::validate_table(t, "table");
  return t;
}

struct RunsSource {
  std::string sweep;
  std::vector<std::string> ids;
  bool params = true, metrics = true;
};

RunsSource runs_source(const nlohmann::json& j) {
  if (!j.is_object()) throw invalid_argument("runs", "runs: must be an object {sweep?, ids?, include?}");
  for (const auto& [k, v] : j.items())
    if (k != "sweep" && k != "ids" && k != "include")
      throw invalid_argument(k, "unknown field 'runs." + k + "'");
  RunsSource s;
  if (j.contains("sweep")) s.sweep = string_field(j, "sweep");
  if (j.contains("ids")) {
    if (!j["ids"].is_array()) throw invalid_argument("ids", "ids: must be an array of run ids");
    for (const auto& id : j["ids"]) {
      if (!id.is_string()) throw invalid_argument("ids", "ids: must be an array of run ids");
      s.ids.push_back(id.get<std::string>());
    }
  }
  if (j.contains("include")) {
    if (!j["include"].is_array()) throw invalid_argument("include", "include: must be an array");
    s.params = s.metrics = false;
    for (const auto& part : j["include"]) {
      if (part == "params")
        s.params = true;
      else if (part == "metrics")
        s.metrics = true;
      else
        throw invalid_argument("include", "include: \"params\" and/or \"metrics\", not " + part.dump());
    }
  }
  return s;
}

/// The work of projecting `rows` rows with `o`, checked against what one synchronous request may do before
/// any of it starts: Force Scheme computes every pair of rows each iteration (rows² × iterations, against
/// limits::kMaxForceSchemeRequestWork); t-SNE spends O(rows) per iteration of both phases (rows ×
/// (exaggeration + main iterations), against limits::kMaxTsneRequestWork). PCA, MDS (landmark above
/// limits::kMaxExactMdsRows) and LAMP (Force Scheme on ⌈√rows⌉ control points) stay within
/// limits::kMaxProjectionRequestRows. Throws Error(payload_too_large) naming "iterations" when the request
/// set them, else "table".
void check_projection_work(std::size_t rows, const projection::ProjectOptions& o) {
  const std::string param = o.iterations > 0 ? "iterations" : "table";
  const std::uint64_t n = rows;
  const char* fix =
      "; use fewer rows or iterations, or `trailscope project` (no limit on work, with progress)";
  if (o.method == projection::Method::force) {
    const std::uint64_t its = o.iterations > 0 ? static_cast<std::uint64_t>(o.iterations) : 100;
    const std::uint64_t work = n * n * its;
    if (work > limits::kMaxForceSchemeRequestWork)
      throw Error(
          Error::Kind::payload_too_large, param,
          "method force on " + std::to_string(n) + " rows × " + std::to_string(its) + " iterations is " +
              std::to_string(work) + " units of work (rows² × iterations), more than one request may do: " +
              std::to_string(limits::kMaxForceSchemeRequestWork) + " (kMaxForceSchemeRequestWork)" + fix);
  } else if (o.method == projection::Method::tsne) {
    const std::uint64_t its = static_cast<std::uint64_t>(o.exaggeration_iterations) +
                              (o.iterations > 0 ? static_cast<std::uint64_t>(o.iterations) : 500);
    const std::uint64_t work = n * its;
    if (work > limits::kMaxTsneRequestWork)
      throw Error(Error::Kind::payload_too_large, param,
                  "method tsne on " + std::to_string(n) + " rows × " + std::to_string(its) +
                      " iterations (early exaggeration included) is " + std::to_string(work) +
                      " units of work (rows × iterations), more than one request may do: " +
                      std::to_string(limits::kMaxTsneRequestWork) + " (kMaxTsneRequestWork)" + fix);
  }
}

}  // namespace

Response create_projection(App& app, const Request& req, const PathParams&) {
  reject_unknown_params(req, {});
  const nlohmann::json j = parse_body_object(req.body, {"table", "runs", "method", "perplexity", "iterations",
                                                        "seed", "k", "standardize", "backend"});
  if (j.contains("table") == j.contains("runs"))
    throw invalid_argument("table", "table: give exactly one of \"table\" (an inline table) and \"runs\"");

  projection::ProjectOptions o;
  o.method = projection::parse_method(j.contains("method") ? string_field(j, "method") : "pca", "method");
  o.backend =
      j.contains("backend") ? parse_backend(string_field(j, "backend"), "backend") : default_backend();
  o.perplexity = number_field(j, "perplexity", o.perplexity);
  const std::int64_t iterations = integer_field(j, "iterations", 0);
  if (iterations < 0 || iterations > limits::kMaxProjectionIterations)
    throw invalid_argument(
        "iterations",
        "iterations: must be in [0, " + std::to_string(limits::kMaxProjectionIterations) + "] (0 = default)");
  o.iterations = static_cast<int>(iterations);
  const std::int64_t seed = integer_field(j, "seed", 42);
  if (seed < 0) throw invalid_argument("seed", "seed: must be ≥ 0");
  o.seed = static_cast<std::uint64_t>(seed);
  o.standardize = bool_field(j, "standardize", true);
  const std::int64_t k = integer_field(j, "k", 10);
  if (k < 1 || k > limits::kMaxQualityK)
    throw invalid_argument("k", "k: must be in [1, " + std::to_string(limits::kMaxQualityK) + "]");

  nlohmann::json row_ids = nullptr, dropped = nlohmann::json::array();
  projection::Table table;
  if (j.contains("table")) {
    table = inline_table(j["table"]);
  } else {
    const RunsSource source = runs_source(j["runs"]);
    std::vector<analysis::RunFigures> figures;
    for (const nlohmann::json& row : select_runs(app, source.sweep, source.ids))
      figures.push_back(run_figures(row));
    analysis::RunTable runs = analysis::run_table(figures, source.params, source.metrics);
    table = std::move(runs.table);
    row_ids = runs.row_ids;
    for (const auto& d : runs.dropped) dropped.push_back({{"name", d.name}, {"why", d.why}});
  }
  check_projection_work(table.rows, o);
  // The compute pool sets req.cancel when the client leaves or the deadline passes: t-SNE and the other
  // iterative methods check it between iterations.
  o.cancel = req.cancel.get();
  nlohmann::json out = projection::to_json(projection::project_with_quality(table, o, static_cast<int>(k)));
  out["row_ids"] = std::move(row_ids);
  out["dropped_columns"] = std::move(dropped);
  return Response::json(200, out);
}

}  // namespace trailscope::server::handlers
