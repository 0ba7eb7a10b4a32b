#include "trailscope/density/raster.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "trailscope/core/error.hpp"

namespace trailscope::density {

std::size_t Raster::valid_count() const {
  return static_cast<std::size_t>(
      std::count_if(values.begin(), values.end(), [](float v) { return !std::isnan(v); }));
}

Raster to_raster(const Aggregate& a, DensityValue value) {
  Raster r;
  r.width = a.width;
  r.height = a.height;
  const std::size_t n = a.count.size();
  r.values.resize(n);
  constexpr float nan = std::numeric_limits<float>::quiet_NaN();
  if (value == DensityValue::count) {
    for (std::size_t i = 0; i < n; ++i) r.values[i] = a.count[i] ? static_cast<float>(a.count[i]) : nan;
    return r;
  }
  if (!a.with_value)
    throw invalid_argument(
        "value", std::string("the aggregate holds no values to average for '") + to_string(value) + "'");
  for (std::size_t i = 0; i < n; ++i)
    r.values[i] =
        a.value_count[i]
            ? static_cast<float>(static_cast<double>(a.value_sum[i]) / kValueScale / a.value_count[i])
            : nan;
  return r;
}

Raster crop(const Raster& r, int margin) {
  if (margin < 0 || 2 * margin >= r.width || 2 * margin >= r.height)
    throw invalid_argument("margin", "cannot crop " + std::to_string(margin) + " px from a " +
                                         std::to_string(r.width) + "x" + std::to_string(r.height) +
                                         " raster");
  if (margin == 0) return r;
  Raster out;
  out.width = r.width - 2 * margin;
  out.height = r.height - 2 * margin;
  out.values.resize(static_cast<std::size_t>(out.width) * out.height);
  for (int y = 0; y < out.height; ++y) {
    const float* src = &r.values[static_cast<std::size_t>(y + margin) * r.width + margin];
    std::copy(src, src + out.width, &out.values[static_cast<std::size_t>(y) * out.width]);
  }
  return out;
}

std::int32_t max_count_inner(const Aggregate& a, int margin) {
  std::int32_t m = 0;
  for (int y = margin; y < a.height - margin; ++y)
    for (int x = margin; x < a.width - margin; ++x)
      m = std::max(m, a.count[static_cast<std::size_t>(y) * a.width + x]);
  return m;
}

}  // namespace trailscope::density
