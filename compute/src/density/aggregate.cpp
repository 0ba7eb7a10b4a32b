#include "trailscope/density/aggregate.hpp"

#include <cmath>

#include "trailscope/core/error.hpp"
#include "trailscope/density/kde.hpp"
#include "trailscope/density/tile_parts.hpp"

namespace trailscope::density {

AggregateResult aggregate(const TrailSet& trails, const Query& query, const Canvas& canvas,
                          const AggregateOptions& options) {
  const double r = options.kernel_radius;
  if (!(r >= 0.0) || r > limits::kMaxKernelRadiusPx)
    throw invalid_argument(
        "kernel_radius", "kernel radius must be in 0.." + std::to_string(limits::kMaxKernelRadiusPx) + " px");
  const int grow = static_cast<int>(std::ceil(r));
  const Canvas work = grow > 0 ? canvas.with_margin(grow) : canvas;
  std::size_t segments = 0;
  const Aggregate agg = aggregate_lines(trails, query, work, options.value, options.max_gap_seconds,
                                        options.backend, &segments);
  AggregateResult out = finish_aggregate(agg, work, options);
  out.segments = segments;
  return out;
}

AggregateResult finish_aggregate(const Aggregate& agg, const Canvas& work, const AggregateOptions& options) {
  const double r = options.kernel_radius;
  if (!(r >= 0.0) || r > limits::kMaxKernelRadiusPx)
    throw invalid_argument(
        "kernel_radius", "kernel radius must be in 0.." + std::to_string(limits::kMaxKernelRadiusPx) + " px");
  AggregateResult out;
  out.path = agg.path;
  out.max_count = max_count_inner(agg, work.margin());
  out.raster =
      crop(r > 0.0 ? kde_smooth(agg, options.value, r) : to_raster(agg, options.value), work.margin());
  return out;
}

}  // namespace trailscope::density
