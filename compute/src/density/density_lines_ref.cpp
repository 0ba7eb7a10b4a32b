// The C++ reference of compute/kernels/density_lines.cl: the same walk, statement for statement, so that
// both give bit-identical aggregates (the reference-versus-OpenCL tests check it).
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "density/density_lines_walk.hpp"
#include "trailscope/density/density_lines.hpp"

namespace trailscope::density {
namespace {

void walk_segment(const std::int64_t* walk, const std::int32_t* cells, int width, int height,
                  const SegmentGrids& g) {
  std::int64_t d = walk[0];
  const std::int64_t inc_x = walk[1], inc_y = walk[2];
  int i = cells[0], j = cells[1];
  const int end_i = cells[2], end_j = cells[3], flags = cells[4];
  const int sx = (flags & 3) - 1, sy = ((flags >> 2) & 3) - 1;
  bool skip = (flags >> 4) & 1;
  const bool has_value = g.value_sum && ((flags >> 5) & 1);
  const std::int64_t value = cells[5];
  for (int guard = width + height + 2; guard > 0; --guard) {
    if (!skip) {
      const std::size_t idx =
          static_cast<std::size_t>(j) * static_cast<std::size_t>(width) + static_cast<std::size_t>(i);
      ++g.count[idx];
      if (has_value) {
        g.value_sum[idx] += value;
        ++g.value_count[idx];
      }
    }
    skip = false;
    if (i == end_i && j == end_j) break;
    if (sx == 0) {
      j += sy;
    } else if (sy == 0) {
      i += sx;
    } else if (d < 0) {
      i += sx;
      d += inc_x;
    } else if (d > 0) {
      j += sy;
      d -= inc_y;
    } else if (sx > 0 && sy < 0) {
      i += sx;
      d += inc_x;
    } else if (sx < 0 && sy > 0) {
      j += sy;
      d -= inc_y;
    } else {
      i += sx;
      j += sy;
      d += inc_x - inc_y;
    }
    if (i < 0 || i >= width || j < 0 || j >= height) break;
  }
}

}  // namespace

void walk_segments(const LineSegments& s, std::size_t first, std::size_t last, const SegmentGrids& g) {
  for (std::size_t k = first; k < last; ++k)
    walk_segment(&s.walk[3 * k], &s.cells[6 * k], s.width, s.height, g);
}

void add_into(Aggregate& to, const Aggregate& from) {
  // Integer sums: the result is the same whichever thread drew which segment.
  const std::size_t pixels = to.count.size();
  for (std::size_t p = 0; p < pixels; ++p) to.count[p] += from.count[p];
  if (to.with_value)
    for (std::size_t p = 0; p < pixels; ++p) {
      to.value_sum[p] += from.value_sum[p];
      to.value_count[p] += from.value_count[p];
    }
}

Aggregate density_lines_ref(const LineSegments& s) {
  Aggregate a = Aggregate::zeros(s.width, s.height, s.with_value);
  const std::size_t n = s.size();
  const std::size_t pixels = a.count.size();
  // Per-thread private grids (cleared, then summed) pay off when there are enough segments to walk
  // per pixel of grid; for few segments, or canvases over kMaxPrivateGridPixels, one thread adds into
  // the result directly. E.g. the Europe day's 127k segments on a 2048² canvas (8.6M pixel visits) still
  // gain from two threads.
  constexpr std::size_t kParallelMinSegments = 16384;
  if (n < kParallelMinSegments || pixels > kMaxPrivateGridPixels || n < pixels / 64) {
    walk_segments(s, 0, n, SegmentGrids::of(a));
  } else {
    tbb::enumerable_thread_specific<Aggregate> local(
        [&] { return Aggregate::zeros(s.width, s.height, s.with_value); });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        walk_segments(s, r.begin(), r.end(), SegmentGrids::of(local.local()));
                      });
    for (const Aggregate& l : local) add_into(a, l);
  }
  a.path = ComputePath::cpu;
  return a;
}

}  // namespace trailscope::density
