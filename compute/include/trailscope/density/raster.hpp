#pragma once
// Raster: the per-pixel numbers that `shade` colours (Datashader's aggregate xarray after its reduction):
// one float per pixel, NaN where there is no data (the pixel is then transparent).
#include <cstdint>
#include <vector>

#include "trailscope/density/density_lines.hpp"

namespace trailscope::density {

struct Raster {
  int width = 0, height = 0;
  std::vector<float> values;  ///< row-major; NaN = no data

  float at(int x, int y) const { return values[static_cast<std::size_t>(y) * width + x]; }
  /// Number of pixels holding data (not NaN).
  std::size_t valid_count() const;
};

/// The aggregate's numbers for `value`: count → the count (NaN where 0, as Datashader masks empty
/// count pixels); altitude / speed → the mean of the valued segments (NaN where none). Throws
/// invalid_argument(`value`) when a mean is asked of an aggregate without values.
Raster to_raster(const Aggregate& a, DensityValue value);

/// The inner part of a raster without a margin of `margin` pixels on each side (2·margin must be less
/// than both sizes; throws invalid_argument(`margin`) otherwise).
Raster crop(const Raster& r, int margin);
/// The same for an aggregate's count grid (values dropped): used for the tile's max_count.
std::int32_t max_count_inner(const Aggregate& a, int margin);

}  // namespace trailscope::density
