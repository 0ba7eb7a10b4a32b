#include "trailscope/density/shade.hpp"

#include <cmath>

#include "trailscope/core/error.hpp"
#include "trailscope/density/colormap.hpp"

namespace trailscope::density {

Image shade(const Raster& raster, const SpanStats& span, const ShadeOptions& options) {
  const Colormap& cmap = colormap(options.cmap, "cmap");
  if (options.min_alpha < 0 || options.min_alpha > 255)
    throw invalid_argument("min_alpha", "min_alpha " + std::to_string(options.min_alpha) + " is outside 0..255");
  Image img;
  img.width = raster.width;
  img.height = raster.height;
  img.rgba.assign(raster.values.size() * 4, 0);
  for (std::size_t i = 0; i < raster.values.size(); ++i) {
    const float v = raster.values[i];
    if (std::isnan(v)) continue;  // transparent
    const double t = span.normalize(v, options.how);
    const auto& c = cmap.rgb[static_cast<std::size_t>(std::lround(t * 255.0))];
    std::uint8_t* px = &img.rgba[4 * i];
    px[0] = c[0];
    px[1] = c[1];
    px[2] = c[2];
    px[3] = options.alpha_ramp
                ? static_cast<std::uint8_t>(std::lround(options.min_alpha + t * (255.0 - options.min_alpha)))
                : 255;
  }
  return img;
}

}  // namespace trailscope::density
