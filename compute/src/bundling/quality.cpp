// Quality figures: ink (pixels covered, with the exact integer line walk of density_lines.hpp) and the
// displacement of the drawn points from their originals.
#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "bundling/result.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/density/density_lines.hpp"

namespace trailscope::bundling {
namespace {

// Bundle pixels on the 32-bit grid of density_lines: 256 units per pixel (sub-pixel endpoints), and
// coordinates clamped to ±2^30 units so that no segment spans half the 2^32 "world" (which
// density_lines would draw the other way round). Only lines more than 4 million px outside the image
// are bent by the clamp.
constexpr std::int64_t kUnitsPerPx = 256;
constexpr double kClampUnits = 1073741824.0;

density::MercPoint to_units(double x, double y) {
  auto u = [](double v) {
    return static_cast<std::int64_t>(std::llround(std::clamp(v * kUnitsPerPx, -kClampUnits, kClampUnits)));
  };
  return {u(x), u(y)};
}

}  // namespace

std::uint64_t ink_pixels(const Polylines& px, int size) {
  if (size < 1 || size > density::kMaxCanvasPx)
    throw invalid_argument("size", "size must be in 1.." + std::to_string(density::kMaxCanvasPx) + " px");
  const density::Canvas canvas(0, 0, kUnitsPerPx, size, size);
  // Segments prepared in fixed chunks of polylines in parallel (a million-edge bundle has tens of
  // millions of segments), concatenated in chunk order.
  constexpr std::size_t kChunk = 4096;
  const std::size_t chunks = (px.size() + kChunk - 1) / kChunk;
  std::vector<density::LineSegments> parts(chunks, density::LineSegments::for_canvas(canvas, false));
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    for (std::size_t e = c * kChunk; e < std::min(px.size(), (c + 1) * kChunk); ++e)
      for (std::size_t k = px.begin(e); k + 1 < px.end(e); ++k)
        density::append_segment(parts[c], canvas, to_units(px.x[k], px.y[k]),
                                to_units(px.x[k + 1], px.y[k + 1]), k > px.begin(e));
  });
  density::LineSegments s = density::LineSegments::for_canvas(canvas, false);
  std::size_t walk = 0, cells = 0;
  for (const auto& part : parts) walk += part.walk.size(), cells += part.cells.size();
  s.walk.reserve(walk), s.cells.reserve(cells);
  for (const auto& part : parts) {
    s.walk.insert(s.walk.end(), part.walk.begin(), part.walk.end());
    s.cells.insert(s.cells.end(), part.cells.begin(), part.cells.end());
  }
  parts.clear();
  const density::Aggregate a = density::density_lines_ref(s);
  return static_cast<std::uint64_t>(
      std::count_if(a.count.begin(), a.count.end(), [](std::int32_t c) { return c > 0; }));
}

namespace detail {

Quality measure_quality(const Polylines& input, const Bundled& r) {
  Quality q;
  const Polylines drawn = relax(r, r.params.relaxation, r.params.max_displacement);
  q.ink_raw_px = ink_pixels(input, r.params.size);
  q.ink_bundled_px = ink_pixels(drawn, r.params.size);
  q.ink_reduction = q.ink_raw_px > 0 ? 1.0 - static_cast<double>(q.ink_bundled_px) / q.ink_raw_px : 0.0;
  double sum = 0;
  for (std::size_t i = 0; i < drawn.points(); ++i) {
    const double dx = drawn.x[i] - r.original.x[i], dy = drawn.y[i] - r.original.y[i];
    const double d = std::sqrt(dx * dx + dy * dy);
    sum += d;
    q.max_displacement_px = std::max(q.max_displacement_px, d);
  }
  q.mean_displacement_px = drawn.points() > 0 ? sum / drawn.points() : 0.0;
  return q;
}

}  // namespace detail
}  // namespace trailscope::bundling
