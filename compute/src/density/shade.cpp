#include "trailscope/density/shade.hpp"

#include <cmath>

#include "trailscope/core/error.hpp"
#include "trailscope/core/text.hpp"
#include "trailscope/density/colormap.hpp"

namespace trailscope::density {
namespace {

struct Shaded {
  std::uint8_t index, alpha;
};

}  // namespace

Image shade(const Raster& raster, const SpanStats& span, const ShadeOptions& options) {
  const Colormap& cmap = colormap(options.cmap, "cmap");
  if (options.min_alpha < 0 || options.min_alpha > 255)
    throw invalid_argument("min_alpha",
                           "min_alpha " + std::to_string(options.min_alpha) + " is outside 0..255");
  if (!(options.min_level >= 0 && options.min_level < 1))
    throw invalid_argument("min_level",
                           "min_level must lie in [0, 1), got " + format_double(options.min_level));
  auto compute = [&](float v) {
    const double t = span.normalize(v, options.how);
    const double level = options.min_level + t * (1.0 - options.min_level);
    return Shaded{static_cast<std::uint8_t>(std::lround(level * 255.0)),
                  options.alpha_ramp ? static_cast<std::uint8_t>(
                                           std::lround(options.min_alpha + t * (255.0 - options.min_alpha)))
                                     : std::uint8_t{255}};
  };
  // Counts are small integers repeated over many pixels: remember their colour instead of searching the
  // eq_hist table again for each pixel (same result, a fraction of the time).
  constexpr int kMemo = 4096;
  std::vector<Shaded> memo(kMemo);
  std::vector<bool> known(kMemo, false);

  Image img;
  img.width = raster.width;
  img.height = raster.height;
  img.rgba.assign(raster.values.size() * 4, 0);
  for (std::size_t i = 0; i < raster.values.size(); ++i) {
    const float v = raster.values[i];
    if (std::isnan(v)) continue;  // transparent
    Shaded s;
    if (v >= 0.0f && v < static_cast<float>(kMemo) && v == std::floor(v)) {
      const auto k = static_cast<std::size_t>(v);
      if (!known[k]) memo[k] = compute(v), known[k] = true;
      s = memo[k];
    } else {
      s = compute(v);
    }
    const auto& c = cmap.rgb[s.index];
    std::uint8_t* px = &img.rgba[4 * i];
    px[0] = c[0];
    px[1] = c[1];
    px[2] = c[2];
    px[3] = s.alpha;
  }
  return img;
}

}  // namespace trailscope::density
