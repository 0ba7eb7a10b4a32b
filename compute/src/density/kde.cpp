#include "trailscope/density/kde.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "trailscope/core/error.hpp"

namespace trailscope::density {
namespace {

// The two separable passes over a row-major grid, outside the grid counting as 0:
//   horizontal: tmp[y][x] = Σ_k w[k] · in[y][x + k − r],   vertical: out[y][x] = Σ_k w[k] · tmp[y + k −
//   r][x],
// each sum taken in ascending k (so the result does not depend on the loop order below). Rows that
// are all zero are skipped: density grids are mostly empty.
std::vector<double> smooth(const std::vector<double>& in, int width, int height,
                           const std::vector<double>& w) {
  const int r = static_cast<int>(w.size() / 2);
  const auto row = [&](int y) { return static_cast<std::size_t>(y) * static_cast<std::size_t>(width); };
  std::vector<double> tmp(in.size(), 0.0);
  std::vector<char> nonzero(static_cast<std::size_t>(height), 0);
  for (int y = 0; y < height; ++y) {
    const double* src = &in[row(y)];
    if (std::all_of(src, src + width, [](double v) { return v == 0.0; })) continue;
    nonzero[static_cast<std::size_t>(y)] = 1;
    double* dst = &tmp[row(y)];
    for (int x = 0; x < width; ++x) {
      const int k0 = std::max(-r, -x), k1 = std::min(r, width - 1 - x);
      double sum = 0.0;
      for (int k = k0; k <= k1; ++k) sum += w[static_cast<std::size_t>(k + r)] * src[x + k];
      dst[x] = sum;
    }
  }
  std::vector<double> out(in.size(), 0.0);
  for (int y = 0; y < height; ++y) {
    double* dst = &out[row(y)];
    const int k0 = std::max(-r, -y), k1 = std::min(r, height - 1 - y);
    for (int k = k0; k <= k1; ++k) {
      if (!nonzero[static_cast<std::size_t>(y + k)]) continue;  // adds exact zeros
      const double wk = w[static_cast<std::size_t>(k + r)];
      const double* src = &tmp[row(y + k)];
      for (int x = 0; x < width; ++x) dst[x] += wk * src[x];
    }
  }
  return out;
}

}  // namespace

std::vector<double> kde_weights(double radius_px) {
  if (!(radius_px > 0.0) || radius_px > 64.0)
    throw invalid_argument("kernel_radius", "kernel radius must be in (0, 64] px");
  const int r = static_cast<int>(std::ceil(radius_px));
  const double sigma = radius_px / 3.0;
  std::vector<double> w(2 * r + 1);
  double sum = 0.0;
  for (int k = -r; k <= r; ++k) {
    const double v = std::abs(k) <= radius_px ? std::exp(-0.5 * (k / sigma) * (k / sigma)) : 0.0;
    w[k + r] = v;
    sum += v;
  }
  for (double& v : w) v /= sum;
  return w;
}

Raster kde_smooth(const Aggregate& a, DensityValue value, double radius_px) {
  const std::vector<double> w = kde_weights(radius_px);
  const std::size_t n = a.count.size();
  Raster out;
  out.width = a.width;
  out.height = a.height;
  out.values.resize(n);
  constexpr float nan = std::numeric_limits<float>::quiet_NaN();
  if (value == DensityValue::count) {
    const std::vector<double> c =
        smooth(std::vector<double>(a.count.begin(), a.count.end()), a.width, a.height, w);
    for (std::size_t i = 0; i < n; ++i) out.values[i] = c[i] > 0.0 ? static_cast<float>(c[i]) : nan;
    return out;
  }
  if (!a.with_value)
    throw invalid_argument(
        "value", std::string("the aggregate holds no values to average for '") + to_string(value) + "'");
  std::vector<double> sums(n);
  for (std::size_t i = 0; i < n; ++i) sums[i] = static_cast<double>(a.value_sum[i]) / kValueScale;
  const std::vector<double> s = smooth(sums, a.width, a.height, w);
  const std::vector<double> c =
      smooth(std::vector<double>(a.value_count.begin(), a.value_count.end()), a.width, a.height, w);
  for (std::size_t i = 0; i < n; ++i) out.values[i] = c[i] > 0.0 ? static_cast<float>(s[i] / c[i]) : nan;
  return out;
}

}  // namespace trailscope::density
