#pragma once
// The second half of the window reads — summary, flight list, positions at an instant — for counts and
// samples found elsewhere: the shards of a database (server/src/store/clickhouse_store.cpp) scan the
// points, and these functions finish the answer with the very code summarize(), list_flights() and
// positions_at() finish theirs with, so both answers are the same bytes.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "trailscope/trails/positions.hpp"
#include "trailscope/trails/quality.hpp"
#include "trailscope/trails/query.hpp"
#include "trailscope/trails/summary.hpp"
#include "trailscope/trails/trail_set.hpp"

namespace trailscope {

/// The bins of a summary, fixed before any point is read, so that partial counts made elsewhere (the
/// shards of a database, server/src/store/clickhouse_store.cpp) land in the same bins as summarize()'s.
struct SummaryLayout {
  static constexpr double kSpeedBin = 0.25;      ///< m/s; the speed percentiles are read from this histogram
  static constexpr int kSpeedBins = 2400;        ///< up to 600 m/s; faster samples land in the last bin
  static constexpr double kAltEdgeNudge = 1e-4;  ///< of an altitude bin (FL100 = 3048 m starts its bin)
  double t_origin = 0;                           ///< start of time bin 0 (Unix s, a multiple of bin_seconds)
  double bin_seconds = 1;                        ///< a "nice" duration
  std::size_t time_bins = 1;                     ///< >= 1
  double alt_scale = 0;                          ///< altitude bins per metre
  double alt_bin_width = 1000;                   ///< in the unit asked
  std::size_t alt_bins = 1;                      ///< from 0 to the top altitude of the data, >= 1
};

/// The layout for `q` and `opts` over data whose first and last points lie at `data_t_min`, `data_t_max`
/// (Unix s) and whose highest known altitude is `top_alt_m` (metres; values below 0 count as 0).
/// Throws invalid_argument for options out of range ("bins", "top").
SummaryLayout summary_layout(const Query& q, const SummaryOptions& opts, double data_t_min, double data_t_max,
                             double top_alt_m);

/// The additive part of a summary: what each matching point adds, in the bins of a SummaryLayout. A point
/// of time t lands in time bin min(floor((t − t_origin) · (1 / bin_seconds)), time_bins − 1), moved up one
/// when t >= t_origin + (bin + 1) · bin_seconds; a known altitude a (m) in bin 0 when a · alt_scale +
/// kAltEdgeNudge <= 0, else min(floor(that), alt_bins − 1); a known speed v in bin
/// min(floor(v · 4), kSpeedBins − 1) (0 when v · 4 <= 0).
struct SummaryCounts {
  SummaryCounts() = default;
  SummaryCounts(const SummaryLayout& l, std::size_t flights);
  std::uint64_t points = 0;
  double t_min = 0, t_max = 0;  ///< first and last matching point (Unix s); ignored when points == 0
  std::vector<std::uint64_t> time, alt, speed;         ///< the three histograms (sizes as in the layout)
  std::uint64_t speed_n = 0;                           ///< points with a known speed
  double speed_sum = 0, speed_min = 0, speed_max = 0;  ///< m/s over them
  std::vector<std::uint32_t> matched;                  ///< matching points per flight (index = flight id)
};

/// The summary from its counts: mean and percentiles, the busiest callsigns (by `flights[i].callsign`
/// of each flight with matched[i] > 0) and `quality` as given.
Summary finish_summary(const SummaryLayout& l, const SummaryOptions& opts, SummaryCounts counts,
                       const std::vector<Flight>& flights, QualityReport quality);

/// The page `page` of `rows` (matching flights, each with points > 0) in the order `sort`, names filled in
/// from `flights` (index = FlightRow::id): the second half of list_flights(), for rows counted elsewhere.
/// Throws invalid_argument("page_size") when out of range.
FlightPage page_flights(std::vector<FlightRow> rows, const std::vector<Flight>& flights, std::size_t page,
                        std::size_t page_size, const FlightSort& sort);

/// One sample of a flight, as PointColumns holds it.
struct PositionSample {
  double t = 0;
  float lat = 0, lon = 0, alt = 0, speed = 0, track = 0, vrate = 0;
  std::uint8_t on_ground = 0;
};

/// Refuses what positions_at() refuses before any work: a non-finite `t` (invalid_argument("t")) and a
/// time window in `q` (invalid_argument("t0"/"t1")).
void validate_positions_query(double t, const Query& q);

/// Flight `flight_id` at `t` as this header describes: from `exact`, a sample at exactly t, when given,
/// else interpolated between `a` (a.t < t) and `b` (t < b.t). Then q's bbox, altitude band and on_ground
/// (not its flight filters: the caller's) decide: false when the position fails them. Names are left
/// empty (finish_positions() fills them).
bool position_from_samples(std::uint32_t flight_id, const PositionSample* exact, const PositionSample& a,
                           const PositionSample& b, double t, const Query& q, Position& out);

/// The answer from the matching positions of any order: Error(payload_too_large, "max_positions") when
/// more than `max_positions`, else ordered by flight id with icao24 and callsign from `flights`
/// (index = flight id).
Positions finish_positions(double t, std::vector<Position> hits, const std::vector<Flight>& flights,
                           std::size_t max_positions);

}  // namespace trailscope
