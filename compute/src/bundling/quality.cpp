// Quality figures: ink (pixels covered, with the exact integer line walk of density_lines.hpp) and the
// displacement of the drawn points from their originals.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <tbb/enumerable_thread_specific.h>
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
  const std::size_t pixels = static_cast<std::size_t>(size) * size;
  // Parts of consecutive polylines, each prepared and rasterised by one thread into its own coverage
  // grid (covered or not: OR-ed, so the result does not depend on the threads), while its segments are
  // still in cache. A million-edge bundle has tens of millions of segments: preparing them all first
  // (48 bytes each) and rasterising them in one call cost more in memory traffic and page faults than
  // the walk itself. A part holds at least pixels / 16 points, so that the per-part cost of a grid
  // (density_lines_ref's result, size² counts) stays small beside its walks; below 16384 segments
  // density_lines_ref walks them on the calling thread.
  const std::size_t part_points = std::max<std::size_t>(16384, pixels / 16);
  auto prepare = [&](std::size_t e0, std::size_t e1) {
    density::LineSegments s = density::LineSegments::for_canvas(canvas, false);
    for (std::size_t e = e0; e < e1; ++e)
      for (std::size_t k = px.begin(e); k + 1 < px.end(e); ++k)
        density::append_segment(s, canvas, to_units(px.x[k], px.y[k]), to_units(px.x[k + 1], px.y[k + 1]),
                                k > px.begin(e));
    return s;
  };
  // Few points (a classic graph): one part, counted directly (no coverage grids to merge).
  if (px.points() <= 4 * part_points) {
    const density::Aggregate a = density::density_lines_ref(prepare(0, px.size()));
    return static_cast<std::uint64_t>(
        std::count_if(a.count.begin(), a.count.end(), [](std::int32_t c) { return c > 0; }));
  }
  std::vector<std::size_t> part_begin{0};  // first polyline of each part
  for (std::size_t e = 0, points = 0; e < px.size(); ++e) {
    points += px.end(e) - px.begin(e);
    if (points >= part_points && e + 1 < px.size()) part_begin.push_back(e + 1), points = 0;
  }
  part_begin.push_back(px.size());
  tbb::enumerable_thread_specific<std::vector<std::uint8_t>> covered(
      [&] { return std::vector<std::uint8_t>(pixels, 0); });
  tbb::parallel_for(std::size_t{0}, part_begin.size() - 1, [&](std::size_t part) {
    const density::LineSegments s = prepare(part_begin[part], part_begin[part + 1]);
    if (s.size() == 0) return;
    const density::Aggregate a = density::density_lines_ref(s);
    std::vector<std::uint8_t>& c = covered.local();
    for (std::size_t p = 0; p < pixels; ++p) c[p] |= a.count[p] > 0;
  });
  std::vector<std::uint8_t> all(pixels, 0);
  for (const auto& c : covered)
    for (std::size_t p = 0; p < pixels; ++p) all[p] |= c[p];
  return static_cast<std::uint64_t>(std::count(all.begin(), all.end(), std::uint8_t{1}));
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
