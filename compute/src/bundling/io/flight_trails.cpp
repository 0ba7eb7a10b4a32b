// Flight trails to bundle (flight_trails.hpp): the same "which points and which segments" as the line
// density (density_lines.hpp, WHAT IS DRAWN), as polylines in 32-bit Web Mercator units.
#include "trailscope/bundling/flight_trails.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/geo/web_mercator.hpp"
#include "trailscope/trails/point_filter.hpp"

namespace trailscope::bundling {
namespace {

constexpr double kWorld = static_cast<double>(geo::kWorldUnits);

/// The query's bbox in Mercator units: west → east (east + one world when the box crosses 180°),
/// north (small y) → south.
std::array<double, 4> bbox_units(const BBox& b) {
  const double x0 = (b.west + 180.0) / 360.0 * kWorld;
  double x1 = (b.east + 180.0) / 360.0 * kWorld;
  if (b.west > b.east) x1 += kWorld;
  return {x0, geo::lat_to_unit_y(b.north) * kWorld, x1, geo::lat_to_unit_y(b.south) * kWorld};
}

}  // namespace

FlightTrails flight_trails(const TrailSet& trails, const Query& query, int size, double max_gap_seconds) {
  if (!(max_gap_seconds > 0))
    throw invalid_argument("max_gap", "max_gap must be > 0 seconds (+infinity: never split)");
  const PointFilter filter(query);
  const PointColumns& pts = trails.points();
  const auto& mx = trails.merc_x();
  const auto& my = trails.merc_y();
  FlightTrails out;
  std::vector<double> xs, ys;
  double lo_x = std::numeric_limits<double>::infinity(), lo_y = lo_x, hi_x = -lo_x, hi_y = -lo_x;

  auto close_run = [&](std::size_t flight) {
    if (xs.size() >= 2) {
      out.lines.add(xs, ys);
      out.flight.push_back(flight);
      for (std::size_t k = 0; k < xs.size(); ++k)
        lo_x = std::min(lo_x, xs[k]), hi_x = std::max(hi_x, xs[k]), lo_y = std::min(lo_y, ys[k]),
        hi_y = std::max(hi_y, ys[k]);
      if (out.lines.size() > limits::kMaxBundleEdges || out.lines.points() > limits::kMaxBundleInputPoints)
        throw Error(Error::Kind::payload_too_large, "query",
                    "the query selects more than " + std::to_string(limits::kMaxBundleEdges) + " trails or " +
                        std::to_string(limits::kMaxBundleInputPoints) +
                        " points to bundle (limits::kMaxBundleEdges, kMaxBundleInputPoints); narrow it");
    }
    xs.clear(), ys.clear();
  };

  for (std::size_t fi = 0; fi < trails.num_flights(); ++fi) {
    const Flight& f = trails.flights()[fi];
    if (!query.may_match(f)) continue;
    const bool all = filter.contains(f);
    std::size_t prev = 0;
    for (std::size_t i = f.begin; i < f.end; ++i) {
      if (!all && !filter(pts, i)) {
        close_run(fi);
        continue;
      }
      if (!xs.empty() && !(pts.t[i] - pts.t[prev] <= max_gap_seconds)) close_run(fi);
      double x = mx[i];
      // Unwrapped along the run: a trail across 180° continues beyond the world's edge instead of
      // jumping back across the map (the density path draws such a segment the short way too).
      if (!xs.empty()) x += std::round((xs.back() - x) / kWorld) * kWorld;
      xs.push_back(x), ys.push_back(static_cast<double>(my[i]));
      prev = i;
    }
    close_run(fi);
  }
  if (out.lines.size() == 0)
    throw Error(Error::Kind::unprocessable, "query",
                "no trail matches the query (runs of at least 2 matching points, split at gaps > max_gap)");

  if (query.bbox) {
    const auto b = bbox_units(*query.bbox);
    out.frame = Frame::view(b[0], b[1], b[2], b[3], size);
  } else {
    // The data's extent; a stationary set gets a box of 1 unit so that the view is not degenerate.
    auto widen = [](double& lo, double& hi) {
      if (hi - lo >= 1) return;
      const double c = (lo + hi) / 2;
      lo = c - 0.5, hi = c + 0.5;
    };
    widen(lo_x, hi_x), widen(lo_y, hi_y);
    out.frame = Frame::view(lo_x, lo_y, hi_x, hi_y, size);
  }
  return out;
}

}  // namespace trailscope::bundling
