#pragma once
// Exports of a window's flights: which flights and points an export holds (planned, and its size checked
// against a limit, before a byte is written), and their CSV rows. The GeoJSON export is one
// flight_geojson(set, id, q, clip = true, ...) Feature per planned flight (trails/summary.hpp), so that an
// exported feature equals GET .../flights/{n}?clip=1 with the same filters.
//
// WHAT IS EXPORTED. The flights with at least one point passing the query (the flights of the flight
// list), in ascending flight id, each with its matching points only (PointFilter: time window, altitude
// band, bbox, on_ground), in time order.
#include <cstdint>
#include <string>
#include <vector>

#include "trailscope/trails/point_filter.hpp"
#include "trailscope/trails/query.hpp"
#include "trailscope/trails/trail_set.hpp"

namespace trailscope {

struct ExportPlan {
  std::vector<std::uint32_t> flights;  ///< flight ids with a matching point, ascending
  std::uint64_t points = 0;            ///< matching points of those flights (the CSV's data rows)
};

/// Plans the export of the window (one parallel pass over the flights the query may match). Throws
/// Error(payload_too_large, "max_points") with "the window holds N points, more than max_points=M: narrow
/// the window or the filters" when the matching points exceed `max_points` (the caller's limit, at most
/// limits::kMaxExportPoints).
ExportPlan plan_export(const TrailSet& set, const Query& q, std::uint64_t max_points);

/// The CSV header line (with "\n"): flight_id,icao24,callsign,t,lat,lon,alt_m,speed_ms,track_deg,
/// vrate_ms,on_ground. Units: Unix seconds, degrees, metres, m/s, degrees, m/s; on_ground 0/1.
const std::string& flights_csv_header();

/// Appends one CSV row per matching point of flight `id` (RFC 4180: a text field holding a comma, quote
/// or line break is quoted). Numbers are the shortest text that reads back to the stored value (double
/// times, float columns as floats); an unknown value is an empty field.
void append_flight_csv(std::string& out, const TrailSet& set, const PointFilter& filter, std::uint32_t id);

/// A text field as RFC 4180 CSV writes it: as is, or quoted with inner quotes doubled when it holds a
/// comma, a quote, CR or LF.
std::string csv_field(const std::string& text);

}  // namespace trailscope
