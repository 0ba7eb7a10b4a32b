// Directional bundling (directional.hpp). Compiled with -ffp-contract=off: the kernels in bundle.cl
// repeat these expressions.
#include "directional.hpp"

#include <algorithm>
#include <cmath>

namespace trailscope::bundling::detail {

double atan2_poly(double y, double x) {
  const double ax = std::fabs(x), ay = std::fabs(y);
  const double mx = ax > ay ? ax : ay, mn = ax > ay ? ay : ax;
  if (mx == 0) return 0;
  const double a = mn / mx, s = a * a;
  // atan(a) on [0, 1] (Abramowitz & Stegun 4.4.49 family, max error ~1e−5 rad).
  double r = ((((0.0208351 * s - 0.085133) * s + 0.180141) * s - 0.3302995) * s + 0.999866) * a;
  if (ay > ax) r = 1.5707963267948966 - r;
  if (x < 0) r = 3.141592653589793 - r;
  if (y < 0) r = -r;
  return r;
}

std::vector<float> point_directions(const Points& p) {
  std::vector<float> d(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const std::uint32_t e = p.edge[i];
    const std::size_t prev = i > p.offsets[e] ? i - 1 : i, next = i + 1 < p.offsets[e + 1] ? i + 1 : i;
    const double dx = static_cast<double>(p.x[next]) - static_cast<double>(p.x[prev]);
    const double dy = static_cast<double>(p.y[next]) - static_cast<double>(p.y[prev]);
    d[i] = static_cast<float>(atan2_poly(dy, dx));
  }
  return d;
}

void site_map(const Points& p, int size, std::vector<std::uint32_t>& sites) {
  std::fill(sites.begin(), sites.end(), 0u);
  const float lim = static_cast<float>(size);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const float x = p.x[i], y = p.y[i];
    if (!(x >= 0.0f && x < lim && y >= 0.0f && y < lim)) continue;
    std::uint32_t& s = sites[static_cast<std::size_t>(static_cast<int>(y)) * size + static_cast<int>(x)];
    s = std::max(s, static_cast<std::uint32_t>(i + 1));
  }
}

double direction_compatibility(double a, double b) {
  double d = a - b;
  if (d > 3.141592653589793) d -= 6.283185307179586;
  if (d < -3.141592653589793) d += 6.283185307179586;
  return 1.0 - 0.6366197723675814 * std::fabs(d);
}

void advect_directional(Points& p, const std::vector<std::uint32_t>& sites, const std::vector<float>& dirs,
                        int size, int radius, double step, double repulsion) {
  const std::vector<float> x = p.x, y = p.y;  // positions before any point moves
  const float lim = static_cast<float>(size);
  const double r2 = static_cast<double>(radius) * radius;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const float z = p.z[i];
    if (!(z > 0.0f) || !(x[i] >= 0.0f && x[i] < lim && y[i] >= 0.0f && y[i] < lim)) continue;
    const double px = x[i], py = y[i], pa = dirs[i];
    const int ix = static_cast<int>(x[i]), iy = static_cast<int>(y[i]);
    double vx = 0, vy = 0, cabs = 0;
    int n = 0;
    for (int sy = std::max(0, iy - radius); sy <= std::min(size - 1, iy + radius); ++sy)
      for (int sx = std::max(0, ix - radius); sx <= std::min(size - 1, ix + radius); ++sx) {
        const std::uint32_t s = sites[static_cast<std::size_t>(sy) * size + sx];
        if (s == 0) continue;
        const std::uint32_t q = s - 1;
        if (p.edge[q] == p.edge[i]) continue;
        const double dx = static_cast<double>(x[q]) - px, dy = static_cast<double>(y[q]) - py;
        const double d2 = dx * dx + dy * dy;
        if (!(d2 < r2)) continue;
        const double w = 1.0 - d2 / r2;
        double c = direction_compatibility(pa, dirs[q]);
        cabs += std::fabs(c);
        ++n;
        if (c < 0) c = c * repulsion;
        vx += dx * (c * w);
        vy += dy * (c * w);
      }
    const double v2 = vx * vx + vy * vy;
    if (n == 0 || v2 < 1e-12) continue;
    const double s = step * static_cast<double>(z) * (cabs / n) / std::sqrt(v2);
    p.x[i] = static_cast<float>(px + s * vx);
    p.y[i] = static_cast<float>(py + s * vy);
  }
}

}  // namespace trailscope::bundling::detail
