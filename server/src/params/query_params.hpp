#pragma once
// Typed parsing of query and path parameters shared by the routes; every error names its parameter.
#include <cstdint>
#include <string>
#include <vector>

#include "routes/http_types.hpp"
#include "trailscope/trails/query.hpp"

namespace trailscope::server::params {

/// The query-filter parameter names (bbox, t0, t1, alt_min, alt_max, alt_unit, icao24, callsign, on_ground).
const std::vector<std::string>& query_keys();
/// query_keys() plus `extra`.
std::vector<std::string> with_query_keys(std::vector<std::string> extra);

/// Non-negative integer parameter in [lo, hi], `fallback` when absent. Throws invalid_argument(name).
std::int64_t integer(const Request& req, const std::string& name, std::int64_t fallback, std::int64_t lo,
                     std::int64_t hi);
/// A finite number query parameter, `fallback` when absent. Throws invalid_argument(name) ("<name>:
/// '<text>' is not a number").
double number(const Request& req, const std::string& name, double fallback);
/// A text query parameter as given, `fallback` when absent.
std::string text(const Request& req, const std::string& name, const std::string& fallback);

/// Integer path parameter in [lo, hi]. Throws invalid_argument(name).
std::int64_t path_integer(const PathParams& p, const std::string& name, std::int64_t lo, std::int64_t hi);

}  // namespace trailscope::server::params
