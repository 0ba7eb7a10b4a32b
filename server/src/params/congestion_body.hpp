#pragma once
// The body of POST /api/v1/congestion (and, built from its flags, of `trailscope congestion`), parsed and
// checked before any work starts, so that every mistake is a 400 naming its field rather than a failed
// job:
//   {"dataset": "europe",
//    "query": {"t0": ..., "t1": ..., "callsign": ..., "icao24": ...},        t0 and t1 required
//    "volumes": {"grid": {"bbox": "w,s,e,n" | [w,s,e,n], "alt_min", "alt_max", "alt_unit"}}
//             | {"sectors": "s1"},                                          a stored sector set
//    "compute": ["occupancy", "entries", "hotspots", "complexity", "separation"],
//    "step": 60, "duration": 60, "method": "interpolated" | "samples",
//    "entry_window": 3600, "entry_step": 1200,
//    "thresholds": {"peak": 40, "sustained": 32, "sustained_steps": 3},
//    "complexity_params": {"heading_deg": 20, "speed_kt": 35, "vrate_fpm": 500}}
// Times are Unix seconds or ISO 8601 (query.hpp's parse_time); durations are seconds; altitudes are in
// alt_unit (ft unless it says m). The values and their ranges are those of congestion::CountsRequest
// (trailscope/congestion/counts.hpp), read by its own parser, which names the parameter in every error.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trailscope/congestion/counts.hpp"

namespace trailscope::server {

/// What a congestion job computes, and from what.
struct CongestionRequest {
  std::string dataset;
  /// The stored sector set of volumes.sectors ("" for the grid); the caller loads its sectors into
  /// counts.sectors (and validates again).
  std::string sectors;
  nlohmann::json volumes;  ///< the body's volumes object, as given (echoed in the result)
  congestion::CountsRequest counts;
  /// The parts of `compute` (default: all but separation, whose all-pairs search costs most).
  bool occupancy = true, entries = true, hotspots = true, complexity = true, separation = false;

  /// Whether any count is asked for (occupancy, entries, hotspots or complexity): they come from one
  /// congestion::count().
  bool runs_counts() const { return occupancy || entries || hotspots || complexity; }
  /// The compute list, in the canonical order.
  std::vector<std::string> compute() const;
};

/// Parses and checks `body` (the JSON object above). Throws invalid_argument naming the field: "body"
/// (not an object), an unknown field's name, "dataset", "query" or a filter's name (bbox and the altitude
/// band belong to volumes.grid), "volumes", "grid", "sectors", "compute", "thresholds",
/// "complexity_params", or any parameter congestion::parse_counts_request names ("t0", "t1", "step",
/// "duration", "method", "peak", ...); Error(payload_too_large) as congestion::validate() throws it
/// (too many periods or grid cells).
CongestionRequest parse_congestion_request(const nlohmann::json& body);

}  // namespace trailscope::server
