#pragma once
// Hand-made bundles for the renderer's tests: polylines given in bundle pixels, with the per-point and
// per-polyline arrays a bundling would attach (computed here from their definitions in bundle.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "trailscope/bundling/render.hpp"

namespace trailscope::bundling::test {

/// A bundle of `lines` (bundle px) in a size × size plane with the identity frame (offsets 0: a view
/// frame, so Viewport::whole shows the plane), original = lines unless given.
inline Bundled make_bundled(const Polylines& lines, int size = 256, const Polylines* original = nullptr) {
  Bundled b;
  b.frame.size = size;
  b.params.relaxation = 0;
  b.params.max_displacement = 0.2;
  b.lines = lines;
  b.original = original ? *original : lines;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::size_t s = lines.begin(i), e = lines.end(i);
    double total = 0;
    std::vector<double> cum{0};
    for (std::size_t k = s + 1; k < e; ++k)
      total += std::hypot(lines.x[k] - lines.x[k - 1], lines.y[k] - lines.y[k - 1]), cum.push_back(total);
    for (double c : cum) b.t.push_back(static_cast<float>(total > 0 ? c / total : 0));
    const Polylines& o = b.original;
    double olen = 0;
    for (std::size_t k = s + 1; k < e; ++k) olen += std::hypot(o.x[k] - o.x[k - 1], o.y[k] - o.y[k - 1]);
    b.length.push_back(static_cast<float>(olen));
    b.angle.push_back(static_cast<float>(std::atan2(o.y[e - 1] - o.y[s], o.x[e - 1] - o.x[s])));
    for (std::size_t k = s; k < e; ++k) {
      const double d = std::hypot(lines.x[k] - o.x[k], lines.y[k] - o.y[k]);
      b.displacement.push_back(static_cast<float>(std::min(1.0, d / (0.2 * olen))));
    }
  }
  return b;
}

/// A straight polyline from (x0, y0) to (x1, y1) with a vertex every `step` px (so the cushion, a
/// per-vertex value, is sampled finely).
inline void add_straight(Polylines& out, double x0, double y0, double x1, double y1, double step = 1) {
  const int n = std::max(1, static_cast<int>(std::ceil(std::hypot(x1 - x0, y1 - y0) / step)));
  std::vector<double> xs, ys;
  for (int k = 0; k <= n; ++k) xs.push_back(x0 + (x1 - x0) * k / n), ys.push_back(y0 + (y1 - y0) * k / n);
  out.add(xs, ys);
}

inline std::array<int, 4> px(const density::Image& img, int x, int y) {
  const std::uint8_t* p = img.pixel(x, y);
  return {p[0], p[1], p[2], p[3]};
}

inline int byte(double v) {
  return static_cast<int>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0));
}

}  // namespace trailscope::bundling::test
