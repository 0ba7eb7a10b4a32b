#pragma once
// TSAN, the binary animation chunk (proto/animation_chunks.md): an AnimationChunk of
// compute/include/trailscope/trails/animation_chunk.hpp encoded for the browser, with times as float32
// relative to the chunk start and positions as float32 EPSG:3857 metres relative to an origin. Also its
// JSON rendering (absolute times and degrees) for `trailscope query animation --json`.
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "trailscope/trails/animation_chunk.hpp"
#include "trailscope/trails/trail_set.hpp"

namespace trailscope::server {

/// The projected origin of a chunk, degrees (longitude in [-180, 180], latitude in [-90, 90]).
struct AnimationOrigin {
  double lon = 0, lat = 0;
};

/// Chunks are aligned: `t` (Unix seconds) must be a multiple of `duration_s`. Throws invalid_argument("t")
/// naming the two nearest aligned starts otherwise.
void check_animation_chunk_start(double t, std::int64_t duration_s);

/// The default origin of every chunk of `set`: the centre of its extent, ((lon_min+lon_max)/2,
/// (lat_min+lat_max)/2); (0, 0) for an empty set.
AnimationOrigin default_animation_origin(const TrailSet& set);

/// Parses "lon,lat" (degrees, lon in [-180, 180], lat in [-85.0511287798, 85.0511287798]). Throws
/// invalid_argument(param) on anything else.
AnimationOrigin parse_animation_origin(const std::string& text, const std::string& param);

/// The TSAN bytes of `chunk` (whose point ranges index `set`), positions relative to `origin`. Sizes are
/// bounded by the chunk's sample count (the caller capped it): 29 bytes per sample, 24 per flight.
std::string encode_animation_chunk(const TrailSet& set, const AnimationChunk& chunk, AnimationOrigin origin);

/// {"t", "duration", "origin": [lon, lat], "count", "samples", "flights": [{"id", "icao24", "callsign",
/// "samples": [{"t", "lat", "lon", "alt_m", "speed_ms", "track_deg", "vrate_ms", "on_ground"}]}]}, with
/// absolute Unix times and degrees as stored; unknown values null.
nlohmann::json animation_chunk_json(const TrailSet& set, const AnimationChunk& chunk, AnimationOrigin origin);

}  // namespace trailscope::server
