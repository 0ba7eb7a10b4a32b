#pragma once
// JSON summaries of an airspace time window: counts, time and altitude histograms, speed statistics and
// the busiest callsigns. One parallel pass over the flights the query may match (flight extents are the
// zone map), then over their points.
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trailscope/trails/quality.hpp"
#include "trailscope/trails/query.hpp"
#include "trailscope/trails/trail_set.hpp"

namespace trailscope {

enum class AltUnit { ft, m };

struct SummaryOptions {
  int bins = 96;  ///< time-histogram bins wanted, 1..limits::kMaxHistogramBins (the bin width is
                  ///< rounded up to a "nice" duration, so there may be fewer)
  AltUnit alt_unit = AltUnit::ft;  ///< unit of the altitude histogram (bins of 1000 ft or 300 m)
  int top_callsigns = 10;          ///< entries in top_callsigns, 0..limits::kMaxTopCallsigns
};

struct Summary {
  std::uint64_t flights = 0;    ///< flights with at least one matching point
  std::uint64_t points = 0;     ///< matching points
  double t_min = 0, t_max = 0;  ///< time of the first and last matching point (Unix s); 0 when none
  struct TimeHistogram {
    double t0 = 0;  ///< start of the first bin (Unix s, a multiple of bin_seconds)
    double bin_seconds = 0;
    std::vector<std::uint64_t> counts;  ///< matching points per bin
  } time_histogram;
  struct AltitudeHistogram {
    AltUnit unit = AltUnit::ft;
    double bin_width = 1000;            ///< in `unit`
    double min = 0;                     ///< lower edge of the first bin, in `unit`
    std::vector<std::uint64_t> counts;  ///< matching points with a known altitude per bin
  } altitude_histogram;
  struct SpeedStats {
    std::uint64_t count = 0;  ///< matching points with a known speed
    /// m/s; min and max exact; mean rounded to 1e-6 m/s (summary.cpp), since the order its sum is
    /// taken in (threads, time buckets, ClickHouse shards) moves its last bits, and the answer must not
    /// depend on which backend or path computed it
    double min = 0, max = 0, mean = 0;
    double p50 = 0, p95 = 0;  ///< m/s, from a 0.25 m/s histogram (so within 0.25 m/s of exact)
  } speed;
  struct CallsignCount {
    std::string callsign;
    std::uint64_t flights = 0, points = 0;
  };
  std::vector<CallsignCount> top_callsigns;  ///< by matching points, then callsign
  /// Implausible values among the matching points (check_quality, trails/quality.hpp).
  QualityReport quality;

  nlohmann::json to_json() const;
  /// One table of the summary as CSV (header line first, "\n" line ends, numbers as the shortest
  /// round-trip text, unknown values empty), the same numbers as to_json():
  ///  - "totals": key,value — flights, points, t_min, t_max, speed_count, speed_min_ms, speed_max_ms,
  ///    speed_mean_ms, speed_p50_ms, speed_p95_ms, implausible_speeds, implausible_altitudes,
  ///    position_jumps (the quality counts);
  ///  - "time_histogram": t0,t1,points — one row per bin [t0, t1) (Unix s);
  ///  - "altitude_histogram": lower,upper,unit,points — one row per bin [lower, upper) in `unit`;
  ///  - "top_callsigns": callsign,flights,points;
  ///  - "quality": kind,flight_id,callsign,t,value — the examples of each kind (speed m/s, altitude m,
  ///    jump m/s), largest first.
  /// Throws invalid_argument("table") for another name.
  std::string to_csv(const std::string& table) const;
  /// The table names to_csv() takes, in its order.
  static const std::vector<std::string>& csv_tables();
};

/// Summarises the points of `set` that match `q`. The time histogram spans [q.t0, q.t1) when given,
/// else the data's time extent. Throws invalid_argument for options out of range ("bins", "top").
/// A query whose only filter is its time window is answered from the set's time index
/// (time_index.hpp): the flights and points of the window only, and its whole hours from counts made at
/// construction; the answer is summarize_scan()'s in every field.
Summary summarize(const TrailSet& set, const Query& q, const SummaryOptions& opts = {});
/// The plain computation: one parallel pass over every flight the query may match, then its points.
Summary summarize_scan(const TrailSet& set, const Query& q, const SummaryOptions& opts = {});

/// One row of the flight list: a flight with the part of it inside the window ("in window": the points
/// that pass the query's point filter — time window, altitude band, bbox, on_ground) and the whole
/// flight's own extent, so a list can show both and say which is which.
struct FlightRow {
  std::uint32_t id = 0;  ///< index of the flight in TrailSet::flights(); stable for a stored dataset
  std::string icao24, callsign;
  // In window: over the matching points only.
  double t_start = 0, t_end = 0;  ///< first and last matching point (Unix s)
  double duration_s = 0;          ///< t_end - t_start (s)
  std::uint64_t points = 0;       ///< matching points
  double alt_max_m = 0;           ///< highest matching altitude (m), NaN when unknown
  // Whole flight: every point of the flight, whatever the window and filters.
  double flight_t_start = 0, flight_t_end = 0;  ///< first and last point (Unix s)
  double flight_duration_s = 0;                 ///< flight_t_end - flight_t_start (s)
  std::uint64_t flight_points = 0;              ///< all points
};

/// The columns a flight list sorts by, named as in FlightRow's JSON.
enum class FlightSortKey {
  id,
  icao24,
  callsign,
  t_start,
  t_end,
  duration_s,
  points,
  alt_max_m,
  flight_t_start,
  flight_t_end,
  flight_duration_s,
  flight_points
};

/// A flight list's order: one column, ascending or descending; rows that tie on it follow in ascending
/// flight id in both directions (so pages never overlap or skip a row); an unknown alt_max_m sorts after
/// every known one in both directions. Text compares byte-wise (callsigns and icao24 are ASCII).
struct FlightSort {
  FlightSortKey key = FlightSortKey::t_start;
  bool descending = false;
};

/// Parses a column name ("t_start", "callsign", ... every FlightSortKey) and an order ("asc" | "desc").
/// Throws invalid_argument naming `sort_param` ("sort must be one of id, icao24, ..., got 'x'") or
/// `order_param` ("order must be 'asc' or 'desc', got 'x'").
FlightSort parse_flight_sort(const std::string& sort, const std::string& order,
                             const std::string& sort_param = "sort",
                             const std::string& order_param = "order");
/// The column names of FlightSortKey, in its order.
const std::vector<std::string>& flight_sort_keys();

struct FlightPage {
  std::uint64_t total = 0;  ///< matching flights over all pages
  std::size_t page = 0, page_size = 0;
  FlightSort sort;
  std::vector<FlightRow> flights;  ///< ordered by `sort`, then id
  /// {"total", "page", "page_size", "sort", "order", "flights": [{"id", "icao24", "callsign", "t_start",
  ///  "t_end", "duration_s", "points", "alt_max_m", "flight_t_start", "flight_t_end", "flight_duration_s",
  ///  "flight_points"}]}.
  nlohmann::json to_json() const;
};

/// Lists matching flights (at least one point passing the query), `page_size` (1..limits::kMaxPageSize)
/// per page from `page` 0, in the order `sort` (default: in-window start, then id). A page past the end
/// is empty. Throws invalid_argument("page_size") when out of range.
FlightPage list_flights(const TrailSet& set, const Query& q, std::size_t page, std::size_t page_size,
                        const FlightSort& sort = {});

/// One flight as a GeoJSON Feature (LineString of [lon, lat, alt_m]) with per-point `times` (Unix s),
/// `altitudes_m` and `speeds_ms` (null where unknown). Only points matching `q` are kept when
/// `clip` is true. Throws not_found("flight_id") for an id out of range, and
/// Error(payload_too_large, "max_points") when more than `max_points` points would be returned.
nlohmann::json flight_geojson(const TrailSet& set, std::size_t flight_id, const Query& q, bool clip,
                              std::size_t max_points);

}  // namespace trailscope
