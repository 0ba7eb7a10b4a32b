#pragma once
// The airspace time-window query: which points of a TrailSet an analyst is looking at. The same struct
// serves the REST API, the CLI and the tile renderer; parse_query() turns string parameters (a URL query
// or CLI flags) into it and names the parameter in every error.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "trailscope/trails/trail_set.hpp"

namespace trailscope {

struct BBox {
  double west = -180, south = -90, east = 180, north = 90;  ///< degrees; west > east crosses 180°
  bool contains(double lat, double lon) const {
    if (lat < south || lat > north) return false;
    return west <= east ? (lon >= west && lon <= east) : (lon >= west || lon <= east);
  }
};

struct Query {
  std::optional<BBox> bbox;
  std::optional<double> t0, t1;            ///< half-open [t0, t1), Unix seconds
  std::optional<double> alt_min, alt_max;  ///< metres, inclusive; points with unknown altitude fail a band
  std::vector<std::string> icao24;         ///< lower-case hex; empty = any
  std::string callsign;  ///< upper-case pattern: `*` any run, `?` one char; no wildcard = prefix
  std::optional<bool> on_ground;

  /// Flight-level filters (icao24, callsign) and the flight's extents against the window.
  bool may_match(const Flight& f) const;
  bool matches_flight_ids(const Flight& f) const;
  // Point-level filters (time, bbox, altitude, on_ground) are applied by PointFilter (point_filter.hpp).
  /// Canonical text of the query (sorted, normalised), used in cache keys and ETags.
  std::string canonical() const;
};

/// Matches `callsign` against a pattern as Query::callsign describes (case already normalised).
bool callsign_matches(const std::string& pattern, const std::string& callsign);

/// Parses a time as Unix seconds ("1514764800", "1514764800.5") or ISO 8601 UTC ("2018-01-01T00:00:00Z",
/// "2018-01-01T00:00:00+01:00", "2018-01-01"). Throws invalid_argument(param).
double parse_time(const std::string& text, const std::string& param);

/// Builds a Query from string parameters: bbox=w,s,e,n  t0  t1  alt_min  alt_max  alt_unit=ft|m (default
/// ft)  icao24=a,b,c  callsign  on_ground=true|false. Unknown keys are ignored here (the caller checks
/// them). Throws invalid_argument naming the parameter on any malformed or out-of-range value, including
/// t1 <= t0, a span above limits::kMaxQuerySpanSeconds and alt_min > alt_max.
Query parse_query(const std::map<std::string, std::string>& params);

}  // namespace trailscope
