#pragma once
// The body of POST /api/v1/bundles, parsed and checked before any work starts, so that every mistake is
// a 400 naming its field rather than a failed job.
#include <limits>
#include <map>
#include <string>

#include "trailscope/bundling/params.hpp"
#include "trailscope/core/backend.hpp"

namespace trailscope::server {

/// A parsed POST /api/v1/bundles body.
struct BundleRequest {
  std::string dataset;                       ///< source.dataset ("" for a graph)
  std::map<std::string, std::string> query;  ///< source.query, as the summary route's parameters
  double max_gap = std::numeric_limits<double>::infinity();  ///< source.max_gap, seconds
  std::string graph;                                         ///< source.graph ("" for a dataset)
  bundling::BundleParams params;
  Backend backend = default_backend();
};

/// Parses and checks the body {"source": {"dataset", "query", "max_gap"} | {"graph"}, "params": {...},
/// "backend"}. Throws invalid_argument naming the field ("body", "source", "query", "max_gap", a
/// parameter's name, "backend", or an unknown field's name).
BundleRequest parse_bundle_request(const std::string& body);

}  // namespace trailscope::server
