#pragma once
// The aggregate stage as one call: prepare the segments of a TrailSet for a canvas, rasterise them
// (density_lines, on the chosen backend), optionally smooth (kde_smooth) on a canvas grown by the kernel
// radius so that the inner area sees its neighbours' data, and crop back to the inner area. The output
// is numbers (a Raster), no colour — Datashader's `Canvas.line(...)` with a reduction.
#include <cstdint>

#include "trailscope/core/backend.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/density/canvas.hpp"
#include "trailscope/density/density_lines.hpp"
#include "trailscope/density/raster.hpp"

namespace trailscope::density {

struct AggregateOptions {
  DensityValue value = DensityValue::count;
  /// KDE radius in pixels, 0 (none) .. limits::kMaxKernelRadiusPx; fractional values are allowed.
  double kernel_radius = 0;
  /// Segments spanning a longer time gap are not drawn (density_lines.hpp, WHAT IS DRAWN).
  double max_gap_seconds = limits::kFlightGapSeconds;
  Backend backend = default_backend();
};

struct AggregateResult {
  Raster raster;                        ///< the canvas's inner area (its own margin cropped too)
  std::int32_t max_count = 0;           ///< largest segment count in the inner area, before smoothing
  std::size_t segments = 0;             ///< prepared segment pieces that met the (grown) canvas
  ComputePath path = ComputePath::cpu;  ///< where density_lines ran
};

/// Aggregates `trails` under `query` on `canvas`. Throws invalid_argument naming `kernel_radius` (outside
/// 0..kMaxKernelRadiusPx or NaN) or `max_gap`, Error(Kind::backend) under opencl_strict() as
/// density_lines does, and what Canvas throws when the grown canvas exceeds kMaxCanvasPx (`width`,
/// `height`).
AggregateResult aggregate(const TrailSet& trails, const Query& query, const Canvas& canvas,
                          const AggregateOptions& options);

}  // namespace trailscope::density
