// Depth to grey, the depth range of a frame, and PSNR (image.hpp).
#include "trailscope/dmd/image.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "trailscope/core/error.hpp"

namespace trailscope::dmd {
namespace {

void check_depth(const DepthImage& d) {
  if (d.width < 1 || d.height < 1 || d.mm.size() != static_cast<std::size_t>(d.width) * d.height)
    throw invalid_argument("depth", "depth image must be non-empty with width * height values");
}

bool valid(float v) {
  return std::isfinite(v) && v > 0;
}

}  // namespace

GreyImage depth_to_grey(const DepthImage& depth, double near_mm, double far_mm) {
  check_depth(depth);
  if (!std::isfinite(near_mm) || near_mm <= 0)
    throw invalid_argument("near",
                           "near must be a finite depth > 0 mm (got " + std::to_string(near_mm) + ")");
  if (!std::isfinite(far_mm) || far_mm <= near_mm)
    throw invalid_argument("far", "far must be a finite depth > near (" + std::to_string(near_mm) +
                                      " mm) (got " + std::to_string(far_mm) + ")");
  GreyImage g;
  g.width = depth.width;
  g.height = depth.height;
  g.pixels.resize(depth.mm.size());
  const double scale = 254.0 / (far_mm - near_mm);
  for (std::size_t i = 0; i < depth.mm.size(); ++i) {
    const float v = depth.mm[i];
    if (!valid(v) || v > far_mm)
      g.pixels[i] = 0;
    else if (v <= near_mm)
      g.pixels[i] = 255;
    else
      g.pixels[i] = static_cast<std::uint8_t>(255 - std::lround((v - near_mm) * scale));
  }
  return g;
}

DepthRange valid_depth_range(const DepthImage& depth) {
  check_depth(depth);
  DepthRange r{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (const float v : depth.mm)
    if (valid(v)) {
      r.near_mm = std::min(r.near_mm, double(v));
      r.far_mm = std::max(r.far_mm, double(v));
    }
  if (!std::isfinite(r.near_mm))
    throw invalid_argument("depth", "depth image has no valid pixel (all holes)");
  return r;
}

double psnr(const GreyImage& a, const GreyImage& b) {
  if (a.width != b.width || a.height != b.height || a.pixels.empty() || a.pixels.size() != b.pixels.size())
    throw invalid_argument("image", "psnr needs two non-empty images of the same size");
  double se = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    const double d = double(a.pixels[i]) - double(b.pixels[i]);
    se += d * d;
  }
  if (se == 0) return std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(255.0 * 255.0 / (se / double(a.pixels.size())));
}

}  // namespace trailscope::dmd
