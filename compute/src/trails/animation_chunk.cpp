#include "trailscope/trails/animation_chunk.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

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

  struct Acc {
    std::vector<ChunkFlight> flights;
    std::size_t samples = 0;
  };
  // Blocks of flights in parallel; the join is left to right, so flights stay in id order.
  Acc acc = tbb::parallel_reduce(
      tbb::blocked_range<std::uint32_t>(0, static_cast<std::uint32_t>(flights.size()), 512), Acc(),
      [&](const tbb::blocked_range<std::uint32_t>& r, Acc a) {
        ChunkFlight c;
        for (std::uint32_t fi = r.begin(); fi != r.end(); ++fi)
          if (range(fi, c)) {
            a.flights.push_back(c);
            a.samples += c.size();
          }
        return a;
      },
      [](Acc a, const Acc& b) {
        a.flights.insert(a.flights.end(), b.flights.begin(), b.flights.end());
        a.samples += b.samples;
        return a;
      });
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
