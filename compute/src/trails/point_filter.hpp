#pragma once
// A Query flattened for the inner loops of the window scans: plain comparisons against ±infinity
// defaults instead of optionals, and a per-flight test that lets a loop skip the point checks when a
// flight lies wholly inside the window (the common case for wide windows).
#include <cmath>
#include <limits>

#include "trailscope/trails/query.hpp"

namespace trailscope::detail {

struct PointFilter {
  double t0 = -std::numeric_limits<double>::infinity(), t1 = std::numeric_limits<double>::infinity();
  bool has_alt = false, has_bbox = false, wraps = false;
  float alt_lo = -std::numeric_limits<float>::infinity(), alt_hi = std::numeric_limits<float>::infinity();
  float south = -90, north = 90, west = -180, east = 180;
  int ground = -1;  ///< -1 any, 0 airborne only, 1 on the ground only

  explicit PointFilter(const Query& q) {
    if (q.t0) t0 = *q.t0;
    if (q.t1) t1 = *q.t1;
    has_alt = q.alt_min || q.alt_max;
    if (q.alt_min) alt_lo = static_cast<float>(*q.alt_min);
    if (q.alt_max) alt_hi = static_cast<float>(*q.alt_max);
    if (q.bbox) {
      has_bbox = true;
      south = static_cast<float>(q.bbox->south), north = static_cast<float>(q.bbox->north);
      west = static_cast<float>(q.bbox->west), east = static_cast<float>(q.bbox->east);
      wraps = q.bbox->west > q.bbox->east;
    }
    if (q.on_ground) ground = *q.on_ground ? 1 : 0;
  }

  bool operator()(const PointColumns& p, std::size_t i) const {
    const double t = p.t[i];
    if (!(t >= t0 && t < t1)) return false;
    if (has_alt) {
      const float a = p.alt[i];
      if (!(a >= alt_lo && a <= alt_hi)) return false;  // NaN fails too
    }
    if (has_bbox) {
      const float lat = p.lat[i], lon = p.lon[i];
      if (!(lat >= south && lat <= north)) return false;
      if (wraps ? !(lon >= west || lon <= east) : !(lon >= west && lon <= east)) return false;
    }
    if (ground >= 0 && p.on_ground[i] != ground) return false;
    return true;
  }

  /// True when every point of `f` passes (so the loop can skip the checks). Altitude bands never take
  /// this path, since a flight's extents say nothing about its points of unknown altitude.
  bool contains(const Flight& f) const {
    if (has_alt || ground >= 0) return false;
    if (!(f.t_min >= t0 && f.t_max < t1)) return false;
    if (has_bbox) {
      if (wraps || f.crosses_antimeridian) return false;
      if (!(f.lat_min >= south && f.lat_max <= north && f.lon_min >= west && f.lon_max <= east)) return false;
    }
    return true;
  }
};

}  // namespace trailscope::detail
