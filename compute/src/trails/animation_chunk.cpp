#include "trailscope/trails/animation_chunk.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <tbb/parallel_for.h>

#include "trailscope/core/error.hpp"

namespace trailscope {

namespace {
void refuse(const char* param) {
  throw invalid_argument(param, std::string(param) +
                                    " does not apply to animation chunks: the player filters positions "
                                    "during playback, and the chunk is the time window");
}
}  // namespace

void check_animation_query(const Query& q) {
  if (q.t0) refuse("t0");
  if (q.t1) refuse("t1");
  if (q.bbox) refuse("bbox");
  if (q.alt_min) refuse("alt_min");
  if (q.alt_max) refuse("alt_max");
  if (q.on_ground) refuse("on_ground");
}

AnimationChunk animation_chunk(const TrailSet& set, double t_start, double duration, const Query& q,
                               std::size_t max_samples) {
  if (!std::isfinite(t_start)) throw invalid_argument("t", "t: the chunk start must be a finite time");
  if (!(duration > 0) || !std::isfinite(duration))
    throw invalid_argument("duration", "duration: the chunk length must be a positive number of seconds");
  check_animation_query(q);

  const auto& pts = set.points();
  const auto& flights = set.flights();
  const double t_end = t_start + duration;
  // The range of one flight, or false when it is absent from the chunk or filtered out.
  const auto range = [&](std::uint32_t fi, ChunkFlight& c) {
    const Flight& f = flights[fi];
    if (!(f.t_min < t_end && f.t_max >= t_start) || f.begin == f.end) return false;
    if (!q.matches_flight_ids(f)) return false;
    const double* const first = pts.t.data() + f.begin;
    const double* const last = pts.t.data() + f.end;
    // t_max >= t_start: lo < last; t_min < t_end: hi > first.
    const double* lo = std::lower_bound(first, last, t_start);
    const double* hi = std::lower_bound(lo, last, t_end);
    if (lo != first) --lo;  // the last sample before the chunk
    if (hi != last) ++hi;   // the first sample at or after its end
    c.flight_id = fi;
    c.begin = f.begin + static_cast<std::uint32_t>(lo - first);
    c.end = f.begin + static_cast<std::uint32_t>(hi - first);
    return true;
  };

  // Fixed blocks of flights in parallel, each into its own list, joined in block order: flights stay in
  // id order and nothing is copied but the final join (the functional parallel_reduce would copy a
  // block's list into every later body call).
  constexpr std::uint32_t kBlock = 2048;
  const auto n = static_cast<std::uint32_t>(flights.size());
  std::vector<std::vector<ChunkFlight>> blocks((n + kBlock - 1) / kBlock);
  tbb::parallel_for(std::size_t{0}, blocks.size(), [&](std::size_t bi) {
    const std::uint32_t lo = static_cast<std::uint32_t>(bi) * kBlock, hi = std::min(n, lo + kBlock);
    ChunkFlight c;
    for (std::uint32_t fi = lo; fi != hi; ++fi)
      if (range(fi, c)) blocks[bi].push_back(c);
  });
  struct {
    std::vector<ChunkFlight> flights;
    std::size_t samples = 0;
  } acc;
  std::size_t count = 0;
  for (const auto& b : blocks) count += b.size();
  acc.flights.reserve(count);
  for (const auto& b : blocks)
    for (const ChunkFlight& c : b) acc.flights.push_back(c), acc.samples += c.size();
  if (acc.samples > max_samples)
    throw Error(Error::Kind::payload_too_large, "duration",
                "the chunk holds " + std::to_string(acc.samples) + " samples, more than " +
                    std::to_string(max_samples) +
                    "; ask for a shorter duration or filter by callsign or icao24");

  AnimationChunk out;
  out.t_start = t_start;
  out.duration = duration;
  out.flights = std::move(acc.flights);
  out.samples = acc.samples;
  return out;
}

}  // namespace trailscope
