#include "trailscope/trails/pick.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/core/text.hpp"
#include "trailscope/geo/web_mercator.hpp"
#include "trailscope/trails/point_filter.hpp"

namespace trailscope {
namespace {

constexpr double kWorld = static_cast<double>(geo::kWorldUnits);
constexpr double kHalfWorld = kWorld / 2;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

void validate_pick(const PickRequest& r) {
  if (!(r.zoom >= limits::kMinZoom && r.zoom <= limits::kMaxZoom))
    throw invalid_argument("zoom", "zoom must lie in " + std::to_string(limits::kMinZoom) + ".." +
                                       std::to_string(limits::kMaxZoom));
  if (r.tile_size != limits::kTileSizeSmall && r.tile_size != limits::kTileSizeLarge)
    throw invalid_argument("tile_size", "tile_size must be " + std::to_string(limits::kTileSizeSmall) +
                                            " or " + std::to_string(limits::kTileSizeLarge));
  if (!(r.tolerance_px > 0) || !std::isfinite(r.tolerance_px))
    throw invalid_argument("tolerance", "tolerance must be a positive number of pixels");
  if (r.limit < 1) throw invalid_argument("limit", "limit must be at least 1");
  if (!std::isfinite(r.x)) throw invalid_argument("x", "x must be a finite number");
  if (!(r.y >= 0 && r.y <= 1)) throw invalid_argument("y", "y must lie in [0, 1] (unit Web Mercator)");
}

namespace {

// Closest point of segment a→b to p: the squared distance and the parameter u in [0, 1].
struct Closest {
  double d2 = std::numeric_limits<double>::infinity(), u = 0;
};
Closest closest(double px, double py, double ax, double ay, double bx, double by) {
  const double dx = bx - ax, dy = by - ay, len2 = dx * dx + dy * dy;
  double u = len2 > 0 ? ((px - ax) * dx + (py - ay) * dy) / len2 : 0.0;
  u = std::clamp(u, 0.0, 1.0);
  const double cx = ax + u * dx - px, cy = ay + u * dy - py;
  return {cx * cx + cy * cy, u};
}

}  // namespace

std::vector<PickHit> pick_flights(const TrailSet& set, const Query& q, const PickRequest& r) {
  validate_pick(r);
  const double world_px = r.tile_size * std::exp2(r.zoom);
  const double units_per_px = kWorld / world_px;
  const double px = (r.x - std::floor(r.x)) * kWorld, py = r.y * kWorld;
  const double reach = r.tolerance_px * units_per_px;  // tolerance in fixed-point units
  const double reach2 = reach * reach;
  const auto& pts = set.points();
  const auto& flights = set.flights();
  const auto& mx = set.merc_x();
  const auto& my = set.merc_y();
  const PointFilter filter(q);

  // The zone map: a flight whose Mercator box (one unit of slack for the float extents' rounding) misses
  // the square of side 2·reach around the point, in every copy of the world, has no segment in reach.
  const auto may_reach = [&](const Flight& f) {
    if (!q.may_match(f)) return false;
    if (f.crosses_antimeridian) return true;
    const double y_lo = geo::lat_to_unit_y(f.lat_max) * kWorld - 1,
                 y_hi = geo::lat_to_unit_y(f.lat_min) * kWorld + 1;
    if (py + reach < y_lo || py - reach > y_hi) return false;
    const double x_lo = geo::lon_to_unit_x(f.lon_min) * kWorld - 1,
                 x_hi = geo::lon_to_unit_x(f.lon_max) * kWorld + 1;
    for (double shift : {-kWorld, 0.0, kWorld})
      if (px + shift + reach >= x_lo && px + shift - reach <= x_hi) return true;
    return false;
  };

  struct Best {
    double d2 = std::numeric_limits<double>::infinity();
    std::size_t i = 0;  // first sample of the segment
    double u = 0, x = 0, y = 0;
  };
  std::vector<Best> best(flights.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, flights.size(), 16), [&](const auto& range) {
    for (std::size_t fi = range.begin(); fi != range.end(); ++fi) {
      const Flight& f = flights[fi];
      if (f.size() < 2 || !may_reach(f)) continue;
      Best& b = best[fi];
      bool prev = filter(pts, f.begin);
      for (std::size_t i = f.begin; i + 1 < f.end; ++i) {
        const bool next = filter(pts, i + 1);
        if (prev && next) {
          const double ax = mx[i], ay = my[i];
          double bx = mx[i + 1];
          const double by = my[i + 1];
          // The short way across 180°, as the density rasteriser draws it.
          if (bx - ax > kHalfWorld)
            bx -= kWorld;
          else if (ax - bx > kHalfWorld)
            bx += kWorld;
          for (double shift : {-kWorld, 0.0, kWorld}) {
            const Closest c = closest(px + shift, py, ax, ay, bx, by);
            if (c.d2 < b.d2) b = {c.d2, i, c.u, ax + c.u * (bx - ax), ay + c.u * (by - ay)};
          }
        }
        prev = next;
      }
    }
  });

  std::vector<std::uint32_t> ids;
  for (std::size_t fi = 0; fi < best.size(); ++fi)
    if (best[fi].d2 <= reach2) ids.push_back(static_cast<std::uint32_t>(fi));
  std::sort(ids.begin(), ids.end(), [&](std::uint32_t a, std::uint32_t b) {
    return best[a].d2 != best[b].d2 ? best[a].d2 < best[b].d2 : a < b;
  });
  if (ids.size() > r.limit) ids.resize(r.limit);

  std::vector<PickHit> out;
  out.reserve(ids.size());
  for (std::uint32_t id : ids) {
    const Best& b = best[id];
    const Flight& f = flights[id];
    PickHit h;
    h.id = id, h.icao24 = f.icao24, h.callsign = f.callsign;
    h.distance_px = std::sqrt(b.d2) / units_per_px;
    h.t = pts.t[b.i] + b.u * (pts.t[b.i + 1] - pts.t[b.i]);
    h.lon = geo::wrap_longitude(geo::merc_x_to_lon(b.x));
    h.lat = geo::merc_y_to_lat(b.y);
    const double a0 = pts.alt[b.i], a1 = pts.alt[b.i + 1];
    h.alt_m = (std::isnan(a0) || std::isnan(a1)) ? kNaN : a0 + b.u * (a1 - a0);
    out.push_back(std::move(h));
  }
  return out;
}

}  // namespace trailscope
