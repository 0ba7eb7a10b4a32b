#pragma once
// A projection with its quality, as one call and one JSON object: what `trailscope project --json` prints
// and POST /api/v1/projections returns (proto/openapi.yaml, ProjectionResult).
#include <cstddef>

#include <nlohmann/json.hpp>

#include "trailscope/projection/projection.hpp"
#include "trailscope/projection/quality.hpp"

namespace trailscope::projection {

struct ProjectionReport {
  Method method = Method::pca;
  std::size_t rows = 0, cols = 0;
  std::vector<std::string> columns;  ///< the table's column names
  Embedding embedding;
  Quality quality;
};

/// Projects `table` with `options` and measures the quality with neighbourhood size `k`, clamped to
/// (rows − 1) / 2 so that small tables still get figures, in the space the method saw (z-scored when
/// options.standardize). Progress: the method's phases, then "quality". Throws as project() and quality(),
/// and Error(invalid_argument, "k") unless 1 ≤ k ≤ limits::kMaxQualityK.
ProjectionReport project_with_quality(const Table& table, const ProjectOptions& options, int k);

/// {method, rows, columns (the column names), path, variant, timings_ms {phase: ms}, perplexity (t-SNE
/// only: the perplexity used, effective_perplexity of the requested one), quality {k,
/// trustworthiness, continuity, neighborhood_preservation, stress, shepard, sampled, queries},
/// coordinates [[x, y], ...]}.
nlohmann::json to_json(const ProjectionReport& r);

}  // namespace trailscope::projection
