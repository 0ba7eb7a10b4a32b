#pragma once
// Losses of separation: pairs of airborne flights closer than the radar separation minima at the same
// instant, found exactly between linearly interpolated samples. Minima after ICAO Doc 4444 (PANS-ATM,
// 16th ed., 2016, ch. 5 and 8): 5 NM horizontally; 1,000 ft vertically, 2,000 ft when either aircraft
// is above FL410 (RVSM airspace ends at FL410, ICAO Doc 9574, 3rd ed., 2012).
//
// The trajectory of a flight is the one positions.hpp (trails/) defines: latitude, longitude and
// altitude linear in time between two consecutive samples of the flight (longitude the short way across
// 180°; two samples exactly 180° apart go the plain way), across any gap inside a flight.
//
// Airborne: a segment between two consecutive samples counts when both samples are airborne
// (on_ground == 0) and both have a known altitude; a segment that touches the ground at either end (a
// take-off or a landing roll) or whose altitude is unknown is never part of an event. An event may thus
// end at the sample where one aircraft lands even if the two are still close.
//
// Infringement at instant t, for flights a and b both on an airborne segment at t:
//     horizontal(t) < minima.horizontal_m   and   |alt_a(t) - alt_b(t)| < V(t),
// with V(t) = minima.vertical_high_m when alt_a(t) > minima.high_above_m or alt_b(t) >
// minima.high_above_m (strictly above; exactly at FL410 the 1,000 ft minimum applies), else
// minima.vertical_m. Both comparisons are strict, so an event has a positive duration; an encounter
// that only touches a minimum is not an event.
//
// Horizontal distance: a local tangent plane on the WGS84 ellipsoid, fixed per sub-piece. The common
// time span of a pair is cut at every sample time of either flight, at the instants either altitude
// crosses minima.high_above_m, and further so that neither aircraft's latitude changes by more than
// kSubPieceLatDeg within one sub-piece. In a sub-piece, with φ0 the mean latitude of the two aircraft at
// its middle instant, M and N the meridional and prime-vertical radii of curvature of WGS84 at φ0:
//     dx = N(φ0)·cos(φ0)·Δλ,   dy = M(φ0)·Δφ   (radians; Δλ the short way round),
// so the relative motion is linear in t and horizontal² is a quadratic: the interval where it is below
// minimum² is solved in closed form, as is the vertical condition (linear), and the two are
// intersected. There is no time step: an encounter of any positive length between two samples is found.
// Error against the geodesic distance (GeographicLib, Karney 2013) at up to 10 NM and |latitude| <= 70°
// (checked by tests/compute/congestion/separation_test.cpp): below 3 m, dominated by φ0 being fixed
// over a sub-piece (latitude drifts by at most kSubPieceLatDeg/2 from the middle).
//
// Events: for each pair, the maximal time intervals where the infringement holds, joined into one event
// when they are contiguous (one ends exactly where the next starts, e.g. at a sample time or at an FL410
// crossing) or when, all the time between them, the pair stays within the vertical minimum (and the
// window's bbox and band) and no more than kJoinToleranceM beyond the horizontal minimum. That tolerance
// is the bound of the tangent-plane error above: the plane changes from one sub-piece to the next, the
// distance jumps there by up to that error, and an encounter that grazes the 5 NM circle exactly at such
// a cut would otherwise come out as two events milliseconds apart. Any other gap separates two events
// (an aircraft that climbs through the vertical minimum and back makes two events, however briefly).
// Events are clipped to the window [t0, t1): an event in progress at t0 starts at t0, one in progress
// at t1 ends at t1 (and then clipped_start / clipped_end say so).
//
// Closest point of approach (CPA) of an event: the instant in [t_start, t_end] of least horizontal
// distance; ties (a constant distance, e.g. two aircraft in formation) go to the earliest instant.
//
// Window filters (Query, trails/query.hpp):
//   - t0 and t1 are required (invalid_argument "t0"/"t1" otherwise); only instants in [t0, t1) count;
//   - callsign and icao24 select flights: both flights of a pair must match;
//   - bbox and the altitude band (alt_min/alt_max) restrict the instants: an instant counts only when
//     both aircraft are inside the bbox and the band (edges included; west > east crosses 180°), solved
//     exactly like the minima (so an event may start or end where one aircraft leaves the box);
//   - on_ground: separation is airborne by definition; on_ground=true is refused (invalid_argument
//     "on_ground"), on_ground=false is accepted and changes nothing.
//
// Candidate pairs come from a spatial hash per time bucket (kBucketSeconds); separation.cpp proves that
// it never misses a pair. Runs on TBB's threads.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trailscope/congestion/volumes.hpp"
#include "trailscope/core/progress.hpp"
#include "trailscope/trails/query.hpp"
#include "trailscope/trails/trail_set.hpp"

namespace trailscope::congestion {

/// Metres per nautical mile (exact, by definition); metres per foot is volumes.hpp's kMetresPerFoot.
inline constexpr double kMetresPerNm = 1852.0;
/// Largest latitude change (degrees) of either aircraft within one sub-piece of the tangent-plane solve.
inline constexpr double kSubPieceLatDeg = 0.01;
/// How far beyond the horizontal minimum (metres) a pair may be between two infringements that are
/// joined into one event (see above): the bound of the tangent-plane error.
inline constexpr double kJoinToleranceM = 3.0;
/// Length of the time buckets of the candidate-pair hash (seconds).
inline constexpr double kBucketSeconds = 60.0;

/// The minima. Every value must be finite and > 0, and vertical_high_m >= vertical_m
/// (invalid_argument naming "horizontal_m", "vertical_m", "vertical_high_m" or "high_above_m";
/// high_above_m may be any finite value).
struct SeparationMinima {
  double horizontal_m = 5 * kMetresPerNm;          ///< 5 NM
  double vertical_m = 1000 * kMetresPerFoot;       ///< 1,000 ft
  double vertical_high_m = 2000 * kMetresPerFoot;  ///< 2,000 ft ...
  double high_above_m = 41000 * kMetresPerFoot;    ///< ... when either aircraft is above FL410
};

/// One loss of separation between two flights.
struct SeparationEvent {
  std::uint32_t flight_a = 0, flight_b = 0;  ///< flight ids (index in TrailSet::flights()), a < b
  std::string icao24_a, callsign_a, icao24_b, callsign_b;  ///< the flights' names (Flight's fields)
  double t_start = 0, t_end = 0;                           ///< Unix seconds; t_start < t_end
  bool clipped_start = false;   ///< the infringement was already going on at the window's t0
  bool clipped_end = false;     ///< ... and was still going on at its t1
  double cpa_t = 0;             ///< Unix seconds, in [t_start, t_end]
  double cpa_horizontal_m = 0;  ///< horizontal distance at cpa_t (tangent plane), metres
  double cpa_vertical_m = 0;    ///< |alt_a - alt_b| at cpa_t, metres
  double cpa_lat_a = 0, cpa_lon_a = 0, cpa_alt_a_m = 0;  ///< degrees, degrees in [-180, 180), metres
  double cpa_lat_b = 0, cpa_lon_b = 0, cpa_alt_b_m = 0;
  double min_vertical_m = 0;  ///< least |alt_a - alt_b| over the event, metres
};

struct SeparationResult {
  double t0 = 0, t1 = 0;  ///< the window, Unix seconds
  SeparationMinima minima;
  /// Ordered by (t_start, flight_a, flight_b).
  std::vector<SeparationEvent> events;
  std::size_t flights = 0;          ///< flights that match the filters and overlap the window
  std::size_t candidate_pairs = 0;  ///< (pair, bucket) candidates the hash produced
  std::size_t pairs_tested = 0;     ///< distinct pairs given to the exact solve
  std::size_t pairs_with_events = 0;

  /// {"t0","t1","minima":{...},"flights","candidate_pairs","pairs_tested","pairs_with_events",
  ///  "count","events":[{"flight_a","flight_b","icao24_a","callsign_a","icao24_b","callsign_b",
  ///  "t_start","t_end","duration_s","clipped_start","clipped_end","cpa":{"t","horizontal_m",
  ///  "vertical_m","a":{"lat","lon","alt_m"},"b":{...}},"min_vertical_m"}]}.
  nlohmann::json to_json() const;
  /// One header line, then one line per event: flight_a,icao24_a,callsign_a,flight_b,icao24_b,
  /// callsign_b,t_start,t_end,duration_s,clipped_start,clipped_end,cpa_t,cpa_horizontal_m,
  /// cpa_vertical_m,cpa_lat_a,cpa_lon_a,cpa_alt_a_m,cpa_lat_b,cpa_lon_b,cpa_alt_b_m,min_vertical_m.
  /// Numbers in shortest round-trip form (core/text.hpp); names quoted when they hold , " or newline.
  std::string to_csv() const;
};

/// Every loss of separation among the flights of `set` in `window`, as this header defines it.
/// Throws invalid_argument for a missing t0/t1, on_ground=true or bad minima (see above);
/// Error(payload_too_large, "max_events") when more than limits::kMaxSeparationEvents events are found;
/// Error(cancelled) when `cancel` is set. `progress` gets the fraction of time buckets done (stage
/// "separation").
SeparationResult losses_of_separation(const TrailSet& set, const Query& window,
                                      const SeparationMinima& minima = {}, const ProgressFn& progress = {},
                                      const CancelToken* cancel = nullptr);

}  // namespace trailscope::congestion
