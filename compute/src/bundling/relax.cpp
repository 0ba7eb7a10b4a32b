// Relaxation toward the original polylines (CUBu Polyline::interpolate; bundle.hpp).
#include <cmath>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "trailscope/bundling/bundle.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::bundling {

Polylines relax(const Bundled& b, double relaxation, double max_displacement) {
  if (!(relaxation >= 0 && relaxation <= 1))
    throw invalid_argument("relaxation",
                           "relaxation must be in [0, 1] (got " + std::to_string(relaxation) + ")");
  if (!(max_displacement >= 0) || !std::isfinite(max_displacement))
    throw invalid_argument("max_displacement",
                           "max_displacement must be >= 0 (got " + std::to_string(max_displacement) + ")");
  if (b.original.points() != b.lines.points() || b.length.size() != b.lines.size())
    throw invalid_argument("bundle", "the bundle's original points or lengths do not match its lines");
  Polylines out = b.lines;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, b.lines.size(), 4096), [&](const auto& range) {
    for (std::size_t e = range.begin(); e < range.end(); ++e) {
      const double cap = max_displacement * b.length[e];
      for (std::size_t i = b.lines.begin(e); i < b.lines.end(e); ++i) {
        const double px = b.lines.x[i], py = b.lines.y[i], ox = b.original.x[i], oy = b.original.y[i];
        const double d = std::sqrt((px - ox) * (px - ox) + (py - oy) * (py - oy));
        double l = 1 - relaxation;
        if (l * d > cap) l = cap / d;  // d > 0 here, since cap >= 0
        out.x[i] = l * px + (1 - l) * ox;
        out.y[i] = l * py + (1 - l) * oy;
      }
    }
  });
  return out;
}

}  // namespace trailscope::bundling
