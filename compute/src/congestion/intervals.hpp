#pragma once
// Private helpers of congestion/: a segment between two samples, interpolated linearly in time as
// trails/positions.hpp defines it, and the time intervals where a linear quantity lies in a range.
#include <algorithm>
#include <cmath>
#include <vector>

#include "trailscope/trails/query.hpp"

namespace trailscope::congestion::detail {

// The short-way longitude step of a segment, with positions.cpp's rule (|Δlon| > 180° in float).
inline double lon_step(float a, float b) {
  double d = static_cast<double>(b) - a;
  if (std::fabs(b - a) > 180.0f) d += d > 0 ? -360.0 : 360.0;
  return d;
}

inline double wrap_lon(double lon) {
  lon = std::remainder(lon, 360.0);  // [-180, 180]
  if (lon >= 180) lon -= 360;
  return lon;
}

// A closed time interval [lo, hi]; empty when hi <= lo (single instants do not count: every condition
// of an infringement is strict, or is a band whose edges have no duration).
struct Iv {
  double lo, hi;
};

// Where v0 + k·t' lies in [lo, hi] for t' in [0, len].
inline Iv linear_within(double v0, double k, double lo, double hi, double len) {
  if (k == 0) return (v0 >= lo && v0 <= hi) ? Iv{0, len} : Iv{0, 0};
  double a = (lo - v0) / k, b = (hi - v0) / k;
  if (a > b) std::swap(a, b);
  return {std::max(a, 0.0), std::min(b, len)};
}

// In-place intersection of a sorted list of disjoint intervals with one interval / another list.
inline void intersect(std::vector<Iv>& list, Iv iv) {
  std::size_t n = 0;
  for (const Iv& x : list) {
    const Iv y{std::max(x.lo, iv.lo), std::min(x.hi, iv.hi)};
    if (y.hi > y.lo) list[n++] = y;
  }
  list.resize(n);
}
inline void intersect(std::vector<Iv>& list, const std::vector<Iv>& other) {
  std::vector<Iv> out;
  for (const Iv& x : list)
    for (const Iv& y : other) {
      const Iv z{std::max(x.lo, y.lo), std::min(x.hi, y.hi)};
      if (z.hi > z.lo) out.push_back(z);
    }
  std::sort(out.begin(), out.end(), [](const Iv& p, const Iv& q) { return p.lo < q.lo; });
  list.swap(out);
}

// Restricts `list` to where a position moving linearly (latitude lat0 + klat·t', longitude lon0 +
// klon·t', unwrapped) is inside `box` (edges included; west > east crosses 180°).
inline void intersect_bbox(std::vector<Iv>& list, double lat0, double klat, double lon0, double klon,
                           const BBox& box, double len) {
  if (list.empty()) return;
  intersect(list, linear_within(lat0, klat, box.south, box.north, len));
  if (list.empty()) return;
  const double east = box.west <= box.east ? box.east : box.east + 360.0;
  std::vector<Iv> lon;
  for (int w = -2; w <= 2; ++w) {
    const Iv x = linear_within(lon0, klon, box.west + 360.0 * w, east + 360.0 * w, len);
    if (x.hi > x.lo) lon.push_back(x);
  }
  std::sort(lon.begin(), lon.end(), [](const Iv& p, const Iv& q) { return p.lo < q.lo; });
  intersect(list, lon);
}

}  // namespace trailscope::congestion::detail
