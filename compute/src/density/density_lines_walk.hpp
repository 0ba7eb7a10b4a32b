#pragma once
// The pixel walk of prepared segments on the CPU (density_lines_ref.cpp), shared by density_lines_ref and
// the one-pass CPU path aggregate_lines (density_lines.cpp). Internal to compute/.
#include <cstddef>
#include <cstdint>

#include "trailscope/density/density_lines.hpp"

namespace trailscope::density {

/// Where walked segments add: an Aggregate's grids (value grids null without values).
struct SegmentGrids {
  std::int32_t* count;
  std::int64_t* value_sum;
  std::int32_t* value_count;
  static SegmentGrids of(Aggregate& a) {
    return {a.count.data(), a.with_value ? a.value_sum.data() : nullptr,
            a.with_value ? a.value_count.data() : nullptr};
  }
};

/// Largest canvas (pixels) drawn with a private grid per thread: above it (16 MiB per count grid) one
/// thread adds into the result directly.
inline constexpr std::size_t kMaxPrivateGridPixels = std::size_t{1} << 22;

/// Walks segments [first, last) of `s` into `g` (sized for s.width × s.height).
void walk_segments(const LineSegments& s, std::size_t first, std::size_t last, const SegmentGrids& g);

/// Adds `from`'s grids into `to`'s (same size and value flag).
void add_into(Aggregate& to, const Aggregate& from);

}  // namespace trailscope::density
