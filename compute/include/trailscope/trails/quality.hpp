#pragma once
// Data quality of flight trails: samples and steps that no aircraft in the data can have flown, counted
// with examples, for the ingest report and the window summary. The limits are physical, not request
// limits, and generous enough that a real civil flight never trips them:
//  - ground speed above kMaxPlausibleSpeedMs (800 kt): the fastest subsonic airliners in the strongest
//    jet streams reach about 720 kt over the ground;
//  - altitude above kMaxPlausibleAltitudeM (FL600, 60,000 ft): above every civil service ceiling (the
//    highest, business jets, certify to FL510);
//  - a position jump: consecutive samples of one flight whose great-circle distance over the time since
//    the previous position was FIRST reported (taken as at least kMinJumpSeconds, the coarsest clock of
//    the formats) exceeds kMaxPlausibleSpeedMs — a position no aircraft could have reached since the
//    previous one. Position reports repeat a stale position for seconds and then catch up (OpenSky's
//    state vectors between position updates); measured from the last repeat, every catch-up would look
//    like a jump, so the time counts from the repeated position's first report.
// Splitting a flight (TrailSetBuilder::build with split_jumps, on by default at ingest) is stricter than
// flagging, because a split is not undone by a look at the map: ordinary noise must never cut a flight.
// Between consecutive samples a (index i-1) and b (index i) a flight is split when
//  - two legs: b comes more than kLegGapSeconds (20 h) after a. No flight in service lasts that long (the
//    longest scheduled non-stop, Singapore–New York, is about 19 h), so this is the next use of the same id
//    (the Europe SO6 day's AFR116: a departure at 00:00 and the next day's at 22:58 under one flight id).
//    It is the time-gap rule of the traffic library's Flight.split() (X. Olive, "traffic, a toolbox for
//    processing and analysing air traffic data", JOSS 2019: split where no sample came for a given time),
//    with a gap long enough for SO6, whose Douglas-Peucker segments routinely last hours. A leg is at least
//    two samples: a lone sample beyond such a gap (an SO6 segment whose clock wrapped at midnight) stays;
//  - a teleport: the step a→b is impossible and the samples on both sides of it agree with their own side:
//    a "step x→y is impossible" when it is at least kJumpSplitMinDistanceM (50 km) long AND implies more
//    than kJumpSplitSpeedMs (twice the 800 kt flag, time from the first report of x's position). Required:
//    a→b, a→c and a'→b impossible (a' = sample i-2, c = sample i+1), a'→a and b→c not. The distance floor
//    keeps GPS jitter between samples seconds apart from ever splitting (at 1 s, 800 kt is only 412 m),
//    and the confirmation on both sides keeps a one-point spike (out and back, the common SO6 glitch: a→b
//    and b→c both impossible, a→c fine) and a glitch at either end of a flight in one piece: those stay
//    flagged as jumps, not split. No split ever leaves a flight of one sample.
// Distances are on the sphere of radius kEarthMeanRadiusM (haversine; the mean radius of WGS84, IUGG),
// whose error against the ellipsoid (< 0.5 %) is far below the margin of the speed limit.
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trailscope/trails/query.hpp"
#include "trailscope/trails/trail_set.hpp"

namespace trailscope {

inline constexpr double kKnot = 1852.0 / 3600.0;                       ///< m/s per knot
inline constexpr double kMaxPlausibleSpeedMs = 800.0 * kKnot;          ///< 800 kt ≈ 411.6 m/s
inline constexpr double kMaxPlausibleAltitudeM = 60000 * 0.3048;       ///< FL600 = 18,288 m
inline constexpr double kMinJumpSeconds = 1.0;                         ///< time step floor of a jump's speed
inline constexpr double kJumpSplitSpeedMs = 2 * kMaxPlausibleSpeedMs;  ///< 1600 kt: a teleport's speed
inline constexpr double kJumpSplitMinDistanceM = 50e3;                 ///< a teleport is at least 50 km
inline constexpr double kLegGapSeconds = 20 * 3600.0;                  ///< a gap this long separates two legs
inline constexpr double kEarthMeanRadiusM = 6371008.8;                 ///< IUGG mean radius of WGS84
/// Examples listed per kind of issue (the largest values; all are counted).
inline constexpr std::size_t kQualityExamples = 10;

/// Great-circle distance (metres) between two points (degrees) on the sphere of kEarthMeanRadiusM.
double great_circle_m(double lat1, double lon1, double lat2, double lon2);

/// The speed (m/s) a step from sample a to sample b implies: great_circle_m / max(|t_b − t_a|,
/// kMinJumpSeconds).
double implied_speed_ms(double t_a, double lat_a, double lon_a, double t_b, double lat_b, double lon_b);

/// One implausible value: where, when and how much.
struct QualityExample {
  std::uint32_t flight_id = 0;  ///< id in the TrailSet (the flight list's id)
  std::string callsign;
  double t = 0;      ///< Unix seconds of the sample (of a jump: the sample after it)
  double value = 0;  ///< m/s for speeds and jumps, metres for altitudes
};

/// Keeps the kQualityExamples largest of `examples`, in check_quality()'s order: value descending, ties by
/// flight id, then time. (A store that gathers candidates elsewhere cuts them with this too.)
void keep_largest_examples(std::vector<QualityExample>& examples);

struct QualityCount {
  std::uint64_t count = 0;
  std::vector<QualityExample> examples;  ///< up to kQualityExamples, largest value first (ties: id, t)
};

struct QualityReport {
  QualityCount speed;     ///< samples with a ground speed above kMaxPlausibleSpeedMs
  QualityCount altitude;  ///< samples with an altitude above kMaxPlausibleAltitudeM
  QualityCount jumps;     ///< steps implying a speed above kMaxPlausibleSpeedMs
  /// {"limits": {"speed_ms", "speed_kt", "altitude_m", "altitude_fl"}, "speed": {"count", "examples":
  /// [{"flight_id", "callsign", "t", "value", "value_kt"}]}, "altitude": {... "value", "value_fl"},
  /// "jumps": {... "value", "value_kt"}}.
  nlohmann::json to_json() const;
};

/// The implausible values among the points of `set` that pass `q` (PointFilter); a jump counts when
/// both of its samples pass. One parallel pass over the flights the query may match.
QualityReport check_quality(const TrailSet& set, const Query& q);
/// One implausible value as check_quality() finds it with every point passing.
struct QualityEvent {
  std::uint32_t flight = 0;  ///< id in the TrailSet
  std::uint32_t point = 0;   ///< index of the sample (of a jump: the sample after it; point − 1 is before)
  std::uint8_t kind = 0;     ///< 0 speed, 1 altitude, 2 jump
  double value = 0;          ///< m/s or metres, as check_quality() reports it
};
/// Every implausible value of `set` (check_quality() with no filter), flight by flight in point order.
/// check_quality(set, q) counts exactly those of flights passing q's flight filters whose sample (and, for
/// a jump, the sample before it) passes q's PointFilter: a jump's value does not depend on the query, and
/// a point passing PointFilter lies within its flight's extents, so Query::may_match() decides nothing
/// more. What a store keeps to answer the quality block without the points (server/src/store/
/// clickhouse_store.cpp). One parallel pass.
std::vector<QualityEvent> quality_events(const TrailSet& set);
/// check_quality() for a time window only, [t0, t1) (±infinity for an open side): read from the set's
/// time index (time_index.hpp), which lists every implausible value at construction, so the cost is the
/// events in the window, not its points; the plain pass when the set has no such index. Same answer.
QualityReport window_quality(const TrailSet& set, double t0, double t1);

}  // namespace trailscope
