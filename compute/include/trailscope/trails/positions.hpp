#pragma once
// Positions at an instant: where every flight of a TrailSet is at time t, interpolated linearly in time
// between the two samples that bracket t. The first of the three scales of the thesis's flight chapter
// (Klein, van der Zwan, Telea, "Dynamic multiscale visualization of flight data", VISAPP 2014): aircraft
// at an instant, before moving trail fragments and whole trail sets. Served by
// GET /api/v1/datasets/{dataset}/positions and `trailscope query positions`.
//
// Which flights: every flight of the set (the store's flights, already split at gaps longer than
// limits::kFlightGapSeconds) whose first sample time <= t <= its last sample time. A flight is
// interpolated across any gap inside it. Flights are skipped by their time extents (the zone map of
// trail_set.hpp), and the bracketing samples are found by a binary search over the flight's times, so
// the cost is O(F + H·log P) for F flights, H hits and P points per flight.
//
// The value of each variable at t, from the samples a (time ta) and b (time tb) with ta < t < tb and
// w = (t - ta) / (tb - ta):
//   - a sample at exactly t is used as is, every value of it (unknown stays unknown);
//   - latitude, altitude, ground speed and vertical rate: a + (b - a)·w;
//   - longitude: the shortest way round, so a flight crossing 180° from 179.5 to -179.5 passes 180, not
//     0; the result lies in [-180, 180). Two samples exactly 180° apart go the plain way (b - a);
//   - track: the shortest arc between the two tracks (350° → 10° passes 0°, not 180°); the result lies in
//     [0, 360). Two tracks exactly 180° apart turn clockwise;
//   - a value unknown (NaN) in either bracketing sample is unknown (NaN, null in JSON);
//   - on_ground: the earlier sample's (a state, not a quantity: it changes at a sample, not between).
//
// Filters, from a Query (query.hpp): bbox, the altitude band and on_ground apply to the interpolated
// position (edges included, exactly as PointFilter applies them to samples: unknown altitude fails any
// band; west > east crosses 180°); callsign and icao24 apply to the flight. A Query's t0/t1 do not apply
// to an instant and are refused (invalid_argument naming "t0" or "t1").
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trailscope/trails/query.hpp"
#include "trailscope/trails/trail_set.hpp"

namespace trailscope {

/// One flight at the instant. Units are SI, as in PointColumns; NaN marks an unknown value.
struct Position {
  std::uint32_t flight_id = 0;  ///< index in TrailSet::flights(): the id of GET .../flights/{flight_id}
  std::string icao24, callsign;
  double lat = 0, lon = 0;  ///< degrees; lat in [-90, 90], lon in [-180, 180)
  double alt_m = 0;         ///< barometric altitude, metres
  double speed_ms = 0;      ///< ground speed, m/s
  double track_deg = 0;     ///< true track, degrees clockwise from north, [0, 360)
  double vrate_ms = 0;      ///< vertical rate, m/s, positive up
  bool on_ground = false;   ///< the earlier bracketing sample's (or the exact sample's)
  bool exact = false;       ///< a sample lies exactly at t and was used as is
};

struct Positions {
  double t = 0;                     ///< the instant, Unix seconds
  std::vector<Position> positions;  ///< ordered by flight_id

  /// {"t", "count", "positions": [{"id", "icao24", "callsign", "lat", "lon", "alt_m", "speed_ms",
  /// "track_deg", "vrate_ms", "on_ground", "exact"}]}; unknown values are null.
  nlohmann::json to_json() const;
  /// A GeoJSON FeatureCollection of Points ([lon, lat]) with the same fields as properties, and "t" and
  /// "count" as foreign members of the collection.
  nlohmann::json to_geojson() const;
};

/// Every flight of `set` present at `t` (Unix seconds) and matching `q`, interpolated at `t` as this
/// header describes, ordered by flight id. Throws invalid_argument("t") for a non-finite t,
/// invalid_argument("t0"/"t1") when `q` has a time window, and Error(payload_too_large,
/// "max_positions") when more than `max_positions` flights match (nothing is built then).
Positions positions_at(const TrailSet& set, double t, const Query& q, std::size_t max_positions);

}  // namespace trailscope
