// project(): option checks, standardisation, and the method switch.
#include <algorithm>
#include <chrono>

#include "projection/detail.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/projection/projection.hpp"

namespace trailscope::projection {

Method parse_method(std::string_view text, const std::string& param) {
  if (text == "pca") return Method::pca;
  if (text == "mds") return Method::mds;
  if (text == "tsne") return Method::tsne;
  if (text == "force") return Method::force;
  if (text == "lamp") return Method::lamp;
  throw invalid_argument(
      param, param + " must be one of pca, mds, tsne, force, lamp, not '" + std::string(text) + "'");
}

const char* to_string(Method m) noexcept {
  switch (m) {
    case Method::pca:
      return "pca";
    case Method::mds:
      return "mds";
    case Method::tsne:
      return "tsne";
    case Method::force:
      return "force";
    case Method::lamp:
      return "lamp";
  }
  return "?";
}

double effective_perplexity(double perplexity, std::size_t rows) {
  if (rows < 4)
    throw invalid_argument("table",
                           "t-SNE needs at least 4 rows (perplexity ≥ 1 needs 3 neighbours); the table has " +
                               std::to_string(rows));
  return std::min(perplexity, static_cast<double>(rows - 1) / 3.0);
}

Embedding project(const Table& table, const ProjectOptions& o) {
  validate_table(table);
  if (o.iterations < 0 || o.iterations > limits::kMaxProjectionIterations)
    throw invalid_argument("iterations", "iterations must be in [0, " +
                                             std::to_string(limits::kMaxProjectionIterations) + "], not " +
                                             std::to_string(o.iterations));
  const auto t0 = std::chrono::steady_clock::now();
  Table t = table;
  if (o.standardize) standardize(t);
  const double t_std =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (o.progress) o.progress(0.0, to_string(o.method));
  Embedding e;
  switch (o.method) {
    case Method::pca:
      e = pca(t, o.backend);
      break;
    case Method::mds:
      e = mds(t, o.seed, o.backend);
      break;
    case Method::force:
      e = force_scheme(t, o.iterations ? o.iterations : 100, o.seed, o.backend);
      break;
    case Method::lamp:
      e = lamp(t, o.seed, o.backend);
      break;
    case Method::tsne: {
      TsneOptions to;
      if (!(o.perplexity >= 1.0) || !(o.perplexity <= limits::kMaxPerplexity))  // before capping it
        throw invalid_argument("perplexity", "perplexity must be in [1, " +
                                                 std::to_string(static_cast<int>(limits::kMaxPerplexity)) +
                                                 "], not " + std::to_string(o.perplexity));
      to.perplexity = effective_perplexity(o.perplexity, t.rows);
      to.iterations = o.iterations ? o.iterations : TsneOptions{}.iterations;
      to.exaggeration_iterations = o.exaggeration_iterations;
      to.exaggeration = o.exaggeration;
      to.learning_rate = o.learning_rate;
      to.theta = o.theta;
      to.seed = o.seed;
      to.progress = o.progress;
      to.cancel = o.cancel;
      e = tsne(t, to, o.backend);
      e.perplexity = to.perplexity;
      break;
    }
  }
  if (o.standardize) e.timings_ms.insert(e.timings_ms.begin(), {"standardize", t_std});
  if (o.progress) o.progress(1.0, "done");
  return e;
}

}  // namespace trailscope::projection
