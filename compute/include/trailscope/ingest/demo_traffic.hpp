#pragma once
// A deterministic generator of one day of plausible US airline traffic, for demos and benchmarks where
// real data is not shippable (OpenSky data is research-only). Routes and their weights come from the
// vega-datasets package (web/node_modules/vega-datasets/data/): airports.csv
// (iata,name,city,state,country,latitude,longitude) and flights-airport.csv (origin,destination,count).
//
// Each flight, in order of its samples:
//  - route: an (origin, destination) pair drawn with probability ∝ count; the path is the WGS84 geodesic
//    (GeographicLib GeodesicLine) between the airport reference points, evaluated exactly every 10 km and
//    interpolated linearly in between (≈ 2 m off the geodesic, and 20× cheaper per sample);
//  - departure: a local-time diurnal profile (almost nothing 00–05 h, banks at 07–09 h and 16–19 h, tapering
//    after 21 h), local time ≈ UTC + round(longitude / 15°) h, wrapped into [day_start, day_start + 1 day);
//  - taxi-out on the ground along the runway axis behind the origin (1.5–3.5 km at ~7 m/s) and a 0–3 min
//    hold, then a take-off roll accelerating to ~150 kt;
//  - climb at ~2,000 ft/min (2,800 below FL100, 2,000 to FL250, 1,400 above, ± 15 % per flight), speed
//    160 → 250 kt by 3,000 ft, 250 kt to FL100, then up to the cruise ground speed at top of climb;
//  - cruise level by route length: ≥ 1,500 km FL330–390, ≥ 700 km FL300–380, ≥ 350 km FL280–340,
//    ≥ 150 km FL200–280, shorter 10,000–16,000 ft; odd thousands eastbound, even westbound (the
//    semicircular rule); 440–480 kt ground speed;
//  - descent on a 3° path to the destination (≈ 2,000 ft/min at 400 kt), slowing to 250 kt below FL100
//    and to ~140 kt at touchdown; a short hop whose climb meets the 3° path never levels off;
//  - landing roll and taxi-in (1–3 km) on the ground beyond the destination reference point.
// Altitudes are above the airports (the inputs have no field elevation), so on the ground alt = 0.
// Every sample carries t, lat, lon, alt (m), speed (m/s), track (deg, the geodesic azimuth), vrate (m/s),
// on_ground. Consecutive samples are 5–10 s apart (uniform per sample).
// Identity: icao24 from the US block a00001–adf7c7, distinct for up to 915,399 flights; callsign = airline
// ICAO prefix weighted by US market share (SWA, AAL, DAL, UAL, SKW, ASA, JBU, ...) + flight number.
#include <cstddef>
#include <cstdint>
#include <string>

#include "trailscope/core/progress.hpp"
#include "trailscope/trails/trail_set.hpp"

namespace trailscope::ingest {

/// Largest fleet and span of the fleet mode (DemoOptions::aircraft, days).
inline constexpr std::size_t kMaxDemoAircraft = 200000;
inline constexpr int kMaxDemoDays = 31;

/// Fleet mode (aircraft > 0): instead of `flights` independent flights on one day, `aircraft` aircraft fly
/// leg after leg for `days` days from day_start: each next leg leaves from the airport the last one landed
/// at (a route out of it drawn ∝ count) after a turnaround of turnaround_min_s..max_s at the gate (not
/// reported); the first off-block lies up to 6 h before day_start so that the fleet is airborne from the
/// first minute, and samples outside [day_start, day_start + days·86400) are dropped. Each aircraft keeps
/// one icao24 and one airline; its flight numbers count up leg by leg, so every leg is its own Flight. At
/// any instant about aircraft × (mean leg time) / (mean leg time + mean turnaround) are in the air or
/// taxiing: ~79 % with the default turnaround (the routes favour short hops, ~11 legs a day). A week of
/// dense traffic, 32,000 aircraft (~25,000 at once) sampled every 120–180 s, is ~100 M points.
struct DemoOptions {
  std::string airports_csv;     ///< path of vega-datasets data/airports.csv
  std::string routes_csv;       ///< path of vega-datasets data/flights-airport.csv
  std::size_t flights = 20000;  ///< flights to generate, 1 .. 1,000,000
  std::uint64_t seed = 42;  ///< same seed (and other options) → identical TrailSet, whatever the thread count
  double day_start = 1704067200;               ///< Unix seconds of the day's 00:00 UTC (default 2024-01-01)
  double sample_min_s = 5, sample_max_s = 10;  ///< sampling interval bounds, seconds, 0 < min ≤ max ≤ 600
  std::size_t aircraft = 0;  ///< fleet mode when > 0 (then `flights` is unused), 0..kMaxDemoAircraft
  int days = 1;              ///< fleet mode: days generated, 1..kMaxDemoDays
  double turnaround_min_s = 1200, turnaround_max_s = 2400;  ///< fleet mode: gate time between legs, seconds
};

/// Generates the traffic: flights in parallel with TBB, each from its own RNG seeded by (seed, index), so
/// the result does not depend on scheduling. About 860 points per flight with the default sampling:
/// 20,000 flights ≈ 17 M points, ~2 s on 2 cores. The TrailSet is assembled directly (two passes: count,
/// then write in place), not through TrailSetBuilder, but equals what the builder would give: flights
/// ordered by start time, icao24, callsign, with the same extents.
/// `progress` is called on the caller's thread with (fraction, "generate") as flights complete, then
/// (0, "assemble") and (1, "assemble").
/// Fleet mode (aircraft > 0) is the same two passes over legs instead of flights: pass 1 runs each
/// aircraft's legs in sequence (counting samples), pass 2 regenerates each leg from its own RNG straight
/// into the columns; its memory is the TrailSet's plus ~60 bytes per leg.
/// Throws Error(not_found, "airports_csv" / "routes_csv") for a missing file, Error(unprocessable, same
/// param) for a file without the expected columns or without a usable route (both airports known, at
/// least 5 km apart, count > 0), Error(invalid_argument, "flights" / "sample_min_s" / "sample_max_s" /
/// "day_start" / "aircraft" / "days" / "turnaround") for out-of-range options, Error(payload_too_large,
/// "aircraft") when a fleet would exceed 2^32−1 points.
TrailSet generate_demo_traffic(const DemoOptions& opts, ProgressFn progress = {});

}  // namespace trailscope::ingest
