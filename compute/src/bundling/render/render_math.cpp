// The per-point and per-pixel formulas of bundle rendering (render.hpp): CUBu's rainbow, HSV, the
// cushion, and the height-field lighting.
#include <algorithm>
#include <cmath>

#include "trailscope/bundling/render.hpp"

namespace trailscope::bundling {

Rgb rainbow(double v) {
  v = std::clamp(v, 0.0, 1.0);
  // dx = 0.8 keeps both ends off the darkest blue and red, so the shortest edges stay visible on black.
  constexpr double dx = 0.8;
  const double w = (6 - 2 * dx) * v + dx;
  auto ch = [](double c) { return std::clamp(c / 2, 0.0, 1.0); };
  return {ch(3 - std::fabs(w - 4) - std::fabs(w - 5)), ch(4 - std::fabs(w - 2) - std::fabs(w - 4)),
          ch(3 - std::fabs(w - 1) - std::fabs(w - 2))};
}

Rgb hsv_to_rgb(double h, double s, double v) {
  h -= std::floor(h);
  s = std::clamp(s, 0.0, 1.0);
  v = std::clamp(v, 0.0, 1.0);
  const double h6 = h * 6;
  const int sector = std::min(5, static_cast<int>(h6));
  const double f = h6 - sector;
  const double p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  switch (sector) {
    case 0:
      return {v, t, p};
    case 1:
      return {q, v, p};
    case 2:
      return {p, v, t};
    case 3:
      return {p, q, v};
    case 4:
      return {t, p, v};
    default:
      return {v, p, q};
  }
}

Cushion cushion(double len, double t) {
  const double c = 0.2 + 0.8 * std::sqrt(std::max(0.0, 1 - 2 * std::fabs(t - 0.5)));
  return {len + (1 - len) * 0.5 * c, (1 - len) + len * 0.5 * c};
}

Lighting light(double gx, double gy) {
  static const double kLightNorm = std::sqrt(0.4 * 0.4 + 0.4 * 0.4 + 1.0);
  const double n = std::sqrt(gx * gx + gy * gy + 1.0);
  // n·l with n = (gx, gy, −1)/|n| and l = (0.4, 0.4, −1)/|l|.
  const double s = std::max(0.0, (0.4 * gx + 0.4 * gy + 1.0) / (n * kLightNorm));
  const double s2 = s * s, s4 = s2 * s2;
  return {0.1 + 0.7 * s, 10.0 * s4 * s4};
}

}  // namespace trailscope::bundling
