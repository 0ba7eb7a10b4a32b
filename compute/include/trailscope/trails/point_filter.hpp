#pragma once
// The point-level part of a Query (time, altitude band, bbox, on_ground), flattened for inner loops:
// plain comparisons against ±infinity defaults instead of optionals. It is the one definition of "a
// point matches": the summary, the flight list, the flight GeoJSON and the density rasteriser all use it,
// so they can never disagree about a point on the edge of a window.
#include <limits>

#include "trailscope/trails/query.hpp"

namespace trailscope {

class PointFilter {
 public:
  explicit PointFilter(const Query& q) {
    if (q.t0) t0_ = *q.t0;
    if (q.t1) t1_ = *q.t1;
    has_alt_ = q.alt_min || q.alt_max;
    if (q.alt_min) alt_lo_ = *q.alt_min;
    if (q.alt_max) alt_hi_ = *q.alt_max;
    if (q.bbox) {
      has_bbox_ = true;
      south_ = q.bbox->south, north_ = q.bbox->north, west_ = q.bbox->west, east_ = q.bbox->east;
      wraps_ = q.bbox->west > q.bbox->east;
    }
    if (q.on_ground) ground_ = *q.on_ground ? 1 : 0;
    every_point_ = !q.t0 && !q.t1 && !has_alt_ && !has_bbox_ && ground_ < 0;
  }

  /// Point i passes: t in [t0, t1); altitude (metres) inside the band, unknown altitude failing any band;
  /// position inside the bbox (edges included; west > east crosses 180°); on_ground as asked. Float
  /// columns are compared as doubles against the query's double bounds.
  bool operator()(const PointColumns& p, std::size_t i) const {
    const double t = p.t[i];
    if (!(t >= t0_ && t < t1_)) return false;
    if (has_alt_) {
      const double a = p.alt[i];
      if (!(a >= alt_lo_ && a <= alt_hi_)) return false;  // NaN fails too
    }
    if (has_bbox_) {
      const double lat = p.lat[i], lon = p.lon[i];
      if (!(lat >= south_ && lat <= north_)) return false;
      if (wraps_ ? !(lon >= west_ || lon <= east_) : !(lon >= west_ && lon <= east_)) return false;
    }
    if (ground_ >= 0 && p.on_ground[i] != ground_) return false;
    return true;
  }

  /// The query has no point-level filter: every point of a matching flight passes.
  bool every_point() const { return every_point_; }

  /// True when every point of `f` passes (so a loop can skip the checks). Altitude bands never take
  /// this path, since a flight's extents say nothing about its points of unknown altitude.
  bool contains(const Flight& f) const {
    if (has_alt_ || ground_ >= 0) return false;
    if (!(f.t_min >= t0_ && f.t_max < t1_)) return false;
    if (has_bbox_) {
      if (wraps_ || f.crosses_antimeridian) return false;
      if (!(f.lat_min >= south_ && f.lat_max <= north_ && f.lon_min >= west_ && f.lon_max <= east_))
        return false;
    }
    return true;
  }

 private:
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  double t0_ = -kInf, t1_ = kInf;
  double alt_lo_ = -kInf, alt_hi_ = kInf;
  double south_ = -90, north_ = 90, west_ = -180, east_ = 180;
  bool has_alt_ = false, has_bbox_ = false, wraps_ = false, every_point_ = false;
  int ground_ = -1;  ///< -1 any, 0 airborne only, 1 on the ground only
};

}  // namespace trailscope
