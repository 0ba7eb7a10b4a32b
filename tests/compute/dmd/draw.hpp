#pragma once
// Shapes drawn for the DMD tests, by direct per-pixel geometry (independent of the code under test).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>

#include "trailscope/dmd/image.hpp"

namespace trailscope::dmd::test {

inline BinaryImage blank(int w, int h) {
  return BinaryImage{w, h, std::vector<std::uint8_t>(static_cast<std::size_t>(w) * h, 0)};
}
inline GreyImage blank_grey(int w, int h, std::uint8_t v = 0) {
  return GreyImage{w, h, std::vector<std::uint8_t>(static_cast<std::size_t>(w) * h, v)};
}

/// Sets every pixel (x, y) with inside(x, y) to `value`.
template <class Image, class V>
void paint(Image& img, V value, const std::function<bool(double, double)>& inside) {
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      if (inside(x, y)) img.pixels[static_cast<std::size_t>(y) * img.width + x] = value;
}

inline std::function<bool(double, double)> disk(double cx, double cy, double r) {
  return [=](double x, double y) { return (x - cx) * (x - cx) + (y - cy) * (y - cy) <= r * r; };
}
inline std::function<bool(double, double)> rect(int x0, int y0, int x1, int y1) {  // inclusive
  return [=](double x, double y) { return x >= x0 && x <= x1 && y >= y0 && y <= y1; };
}
inline std::function<bool(double, double)> ellipse(double cx, double cy, double rx, double ry) {
  return [=](double x, double y) {
    const double u = (x - cx) / rx, v = (y - cy) / ry;
    return u * u + v * v <= 1;
  };
}
/// A vertical capsule: the segment (cx, y0)-(cx, y1) dilated by r.
inline std::function<bool(double, double)> capsule(double cx, double y0, double y1, double r) {
  return [=](double x, double y) {
    const double yy = std::clamp(y, y0, y1);
    return (x - cx) * (x - cx) + (y - yy) * (y - yy) <= r * r;
  };
}

}  // namespace trailscope::dmd::test
