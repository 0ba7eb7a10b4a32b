// A projection with its quality, and its JSON (projection/report.hpp).
#include "trailscope/projection/report.hpp"

#include <algorithm>
#include <string>

#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"

namespace trailscope::projection {

ProjectionReport project_with_quality(const Table& table, const ProjectOptions& options, int k) {
  if (k < 1 || k > limits::kMaxQualityK)
    throw invalid_argument(
        "k", "k: must be in [1, " + std::to_string(limits::kMaxQualityK) + "], got " + std::to_string(k));
  ProjectionReport r;
  r.method = options.method;
  r.rows = table.rows;
  r.cols = table.cols;
  r.columns = table.columns;
  r.embedding = project(table, options);
  if (options.progress) options.progress(1.0, "quality");
  // Quality is measured in the space the method saw, or a z-scored projection would look poor against the
  // raw columns it never saw.
  Table seen = table;
  if (options.standardize) standardize(seen);
  QualityOptions qo;
  qo.k = std::max(1, std::min(k, static_cast<int>((table.rows - 1) / 2)));
  qo.seed = options.seed;
  qo.backend = options.backend;
  r.quality = quality(seen, r.embedding.xy, qo);
  return r;
}

nlohmann::json to_json(const ProjectionReport& r) {
  const Quality& q = r.quality;
  nlohmann::json j = {{"method", to_string(r.method)},
                      {"rows", r.rows},
                      {"columns", r.columns},
                      {"path", r.embedding.path},
                      {"variant", r.embedding.variant},
                      {"timings_ms", nlohmann::json::object()},
                      {"quality",
                       {{"k", q.k},
                        {"trustworthiness", q.trustworthiness},
                        {"continuity", q.continuity},
                        {"neighborhood_preservation", q.neighborhood_preservation},
                        {"stress", q.stress},
                        {"shepard", q.shepard},
                        {"sampled", q.sampled},
                        {"queries", q.queries}}}};
  for (const auto& [phase, ms] : r.embedding.timings_ms) j["timings_ms"][phase] = ms;
  if (r.method == Method::tsne) j["perplexity"] = r.embedding.perplexity;
  nlohmann::json coords = nlohmann::json::array();
  for (std::size_t i = 0; i < r.embedding.rows; ++i) coords.push_back({r.embedding.x(i), r.embedding.y(i)});
  j["coordinates"] = std::move(coords);
  return j;
}

}  // namespace trailscope::projection
