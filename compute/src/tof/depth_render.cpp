#include "trailscope/tof/depth_render.hpp"

#include <algorithm>
#include <cmath>

#include "tof/manifest.hpp"
#include "trailscope/tof/depth_video_io.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::tof {

namespace {
DepthRange quantiles(std::vector<float>& valid, double lo, double hi) {
  if (!(lo >= 0 && lo < hi && hi <= 1))
    throw invalid_argument("quantile", "quantiles must satisfy 0 <= lo < hi <= 1");
  if (valid.empty()) return {0, 1000};
  // nth_element twice instead of a sort: a frame has up to a million pixels and this runs per request.
  const auto at = [&](double q) {
    const auto k = static_cast<std::size_t>(std::llround(q * static_cast<double>(valid.size() - 1)));
    std::nth_element(valid.begin(), valid.begin() + static_cast<std::ptrdiff_t>(k), valid.end());
    return static_cast<double>(valid[k]);
  };
  DepthRange r{at(lo), at(hi)};
  if (r.max_mm - r.min_mm < 1) r.max_mm = r.min_mm + 1;  // a flat wall still gets a usable range
  return r;
}

void check_size(std::size_t n, int width, int height, const char* param) {
  if (width < 1 || height < 1 || n != static_cast<std::size_t>(width) * static_cast<std::size_t>(height))
    throw invalid_argument(param, std::string(param) + ": " + std::to_string(n) + " values for a " +
                                      std::to_string(width) + "x" + std::to_string(height) + " image");
}
}  // namespace

DepthRange depth_quantile_range(const std::vector<float>& depth_mm, double lo, double hi) {
  return depth_quantile_range(std::vector<const std::vector<float>*>{&depth_mm}, lo, hi);
}

DepthRange depth_quantile_range(const std::vector<const std::vector<float>*>& frames, double lo, double hi) {
  std::vector<float> valid;
  for (const auto* f : frames)
    for (float d : *f)
      if (!std::isnan(d)) valid.push_back(d);
  return quantiles(valid, lo, hi);
}

density::Image render_depth(const std::vector<float>& depth_mm, int width, int height,
                            const DepthRange& range, const density::Colormap& cmap) {
  if (!std::isfinite(range.min_mm) || !std::isfinite(range.max_mm) || !(range.min_mm < range.max_mm))
    throw invalid_argument("min", "the depth range must have min < max (mm), got " +
                                      std::to_string(range.min_mm) + ".." + std::to_string(range.max_mm));
  check_size(depth_mm.size(), width, height, "depth");
  density::Image img;
  img.width = width, img.height = height;
  img.rgba.assign(depth_mm.size() * 4, 0);
  const double scale = 255.0 / (range.max_mm - range.min_mm);
  for (std::size_t i = 0; i < depth_mm.size(); ++i) {
    const float d = depth_mm[i];
    if (std::isnan(d)) continue;  // hole: transparent black
    const double t = std::clamp((range.max_mm - d) * scale, 0.0, 255.0);
    const auto& c = cmap.rgb[static_cast<std::size_t>(std::lround(t))];
    std::uint8_t* p = &img.rgba[i * 4];
    p[0] = c[0], p[1] = c[1], p[2] = c[2], p[3] = 255;
  }
  return img;
}

density::Image render_amplitude(const std::vector<float>& amplitude, int width, int height) {
  density::Image img;
  if (width < 1 || height < 1) check_size(amplitude.size(), width, height, "amplitude");
  img.width = width, img.height = height;
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  img.rgba.assign(n * 4, 0);
  for (std::size_t i = 0; i < n; ++i) img.rgba[i * 4 + 3] = 255;
  if (amplitude.empty()) return img;
  check_size(amplitude.size(), width, height, "amplitude");
  double top = 0;
  for (float a : amplitude)
    if (std::isfinite(a)) top = std::max(top, static_cast<double>(a));
  if (top <= 0) return img;
  // Log scale: amplitude falls with the square of the range, so linear grey would show only the nearest
  // surfaces.
  const double inv = 255.0 / std::log1p(top);
  for (std::size_t i = 0; i < n; ++i) {
    const double a = std::isfinite(amplitude[i]) ? std::max(0.0, static_cast<double>(amplitude[i])) : 0.0;
    const auto g = static_cast<std::uint8_t>(std::lround(std::clamp(std::log1p(a) * inv, 0.0, 255.0)));
    std::uint8_t* p = &img.rgba[i * 4];
    p[0] = p[1] = p[2] = g;
  }
  return img;
}

nlohmann::json truth_to_json(const FrameTruth& truth) {
  return detail::truth_to_json(truth);
}

DepthRange video_depth_range(const DepthVideoReader& reader) {
  std::vector<std::vector<float>> depth;
  for (std::size_t i = 0; i < std::min(kDepthRangeFrames, reader.size()); ++i)
    depth.push_back(reader.read_frame(i).depth_mm);
  std::vector<const std::vector<float>*> frames;
  for (const auto& d : depth) frames.push_back(&d);
  return depth_quantile_range(frames);
}

}  // namespace trailscope::tof
