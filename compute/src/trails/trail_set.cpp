#include "trailscope/trails/trail_set.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>

#include "trailscope/geo/web_mercator.hpp"
#include "trailscope/trails/time_index.hpp"

namespace trailscope {

void PointColumns::reserve(std::size_t n) {
  t.reserve(n), lat.reserve(n), lon.reserve(n), alt.reserve(n);
  speed.reserve(n), track.reserve(n), vrate.reserve(n), on_ground.reserve(n);
}

void PointColumns::resize(std::size_t n) {
  t.resize(n), lat.resize(n), lon.resize(n), alt.resize(n);
  speed.resize(n), track.resize(n), vrate.resize(n), on_ground.resize(n);
}

void compute_extents(Flight& f, const PointColumns& p) {
  constexpr float inf = std::numeric_limits<float>::infinity();
  f.t_min = f.begin < f.end ? p.t[f.begin] : 0, f.t_max = f.begin < f.end ? p.t[f.end - 1] : 0;
  f.lat_min = f.lon_min = f.alt_min = inf;
  f.lat_max = f.lon_max = f.alt_max = -inf;
  f.crosses_antimeridian = false;
  for (std::size_t i = f.begin; i < f.end; ++i) {
    f.lat_min = std::min(f.lat_min, p.lat[i]), f.lat_max = std::max(f.lat_max, p.lat[i]);
    f.lon_min = std::min(f.lon_min, p.lon[i]), f.lon_max = std::max(f.lon_max, p.lon[i]);
    const float a = p.alt[i];
    if (a == a) f.alt_min = std::min(f.alt_min, a), f.alt_max = std::max(f.alt_max, a);
    if (i > f.begin && std::fabs(p.lon[i] - p.lon[i - 1]) > 180.0f) f.crosses_antimeridian = true;
  }
  if (f.alt_min > f.alt_max) f.alt_min = f.alt_max = std::numeric_limits<float>::quiet_NaN();
}

TrailSet::TrailSet(PointColumns points, std::vector<Flight> flights)
    : points_(std::move(points)), flights_(std::move(flights)) {
  const std::size_t n = points_.size();
  merc_x_.resize(n);
  merc_y_.resize(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 15), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      merc_x_[i] = geo::lon_to_merc_x(points_.lon[i]);
      merc_y_[i] = geo::lat_to_merc_y(points_.lat[i]);
    }
  });
  if (flights_.empty()) return;
  time_index_ = std::make_shared<const TimeIndex>(points_, flights_);
  t_min_ = std::numeric_limits<double>::infinity(), t_max_ = -t_min_;
  lat_min_ = lon_min_ = std::numeric_limits<float>::infinity();
  lat_max_ = lon_max_ = -lat_min_;
  for (const Flight& f : flights_) {
    t_min_ = std::min(t_min_, f.t_min), t_max_ = std::max(t_max_, f.t_max);
    lat_min_ = std::min(lat_min_, f.lat_min), lat_max_ = std::max(lat_max_, f.lat_max);
    lon_min_ = std::min(lon_min_, f.lon_min), lon_max_ = std::max(lon_max_, f.lon_max);
  }
}

const TimeIndex& TrailSet::time_index() const {
  static const TimeIndex none;
  return time_index_ ? *time_index_ : none;
}

}  // namespace trailscope
