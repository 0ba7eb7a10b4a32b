#pragma once
// Animation chunks: which flights, and which of their samples, a player needs to draw every instant of a
// half-open time interval [t_start, t_start + duration). The second of the three scales of the thesis's
// flight chapter (Klein, van der Zwan, Telea, "Dynamic multiscale visualization of flight data", VISAPP
// 2014): moving aircraft, between positions at an instant (positions.hpp) and whole trail sets. The
// server encodes a chunk as TSAN (proto/animation_chunks.md, server/src/formats/animation_chunk.hpp) for
// GET /api/v1/datasets/{dataset}/animation and `trailscope query animation`.
//
// Which flights: every flight of the set (the store's flights, split at gaps longer than
// limits::kFlightGapSeconds) present at some instant of the chunk, t_min < t_start + duration and
// t_max >= t_start; a flight starting exactly at the chunk's end belongs to the next chunk only.
//
// Which samples: every sample with t_start <= t < t_start + duration, plus the last sample before t_start
// (if any) and the first at or after t_start + duration (if any). These form one contiguous range of the
// flight's points, and every instant of the chunk at which the flight is present is bracketed by two
// samples of the range (or lies exactly on one), so interpolating the range with positions_at()'s rule
// (positions.hpp) gives positions_at()'s answer for that flight at every instant of the chunk.
//
// Cost: flights are skipped by their time extents (the zone map of trail_set.hpp) and the two ends of a
// range are found by binary searches over the flight's times: O(F + H·log P) for F flights, H flights in
// the chunk and P points per flight, in parallel over flights. Nothing is copied: the chunk names point
// ranges of the set, which must outlive it.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "trailscope/trails/query.hpp"
#include "trailscope/trails/trail_set.hpp"

namespace trailscope {

/// One flight of a chunk: the points [begin, end) of TrailSet::points(), time-sorted, end > begin.
struct ChunkFlight {
  std::uint32_t flight_id = 0;  ///< index in TrailSet::flights(): the id of GET .../flights/{flight_id}
  std::uint32_t begin = 0, end = 0;
  std::uint32_t size() const { return end - begin; }
};

struct AnimationChunk {
  double t_start = 0;                ///< Unix seconds
  double duration = 0;               ///< seconds, > 0
  std::vector<ChunkFlight> flights;  ///< ordered by flight_id
  std::size_t samples = 0;           ///< the sum of the flights' sizes
};

/// Refuses the filters of `q` that do not apply to a chunk, as animation_chunk() does (so that a server
/// can refuse them before answering from a cache). Throws invalid_argument naming the first of t0, t1,
/// bbox, alt_min, alt_max, on_ground that is set.
void check_animation_query(const Query& q);

/// The chunk [t_start, t_start + duration) of `set`: the flights matching `q` and their samples, as this
/// header describes. Only the flight-level filters of `q` (callsign, icao24) apply: a chunk is a time
/// interval, and position filters belong to the player, which applies them at every instant without
/// refetching; so q.t0/t1, q.bbox, q.alt_min/alt_max and q.on_ground are refused by name
/// (invalid_argument "t0", "t1", "bbox", "alt_min", "alt_max", "on_ground"). Throws invalid_argument("t")
/// for a non-finite t_start, invalid_argument("duration") unless 0 < duration < infinity, and
/// Error(payload_too_large, "duration") when the chunk holds more than `max_samples` samples (counted
/// before anything is built).
AnimationChunk animation_chunk(const TrailSet& set, double t_start, double duration, const Query& q,
                               std::size_t max_samples);

}  // namespace trailscope
