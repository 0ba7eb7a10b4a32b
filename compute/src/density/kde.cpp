#include "trailscope/density/kde.hpp"

#include <cmath>
#include <limits>

#include "trailscope/core/error.hpp"

namespace trailscope::density {
namespace {

// One separable pass over a row-major grid: out[y][x] = Σ_k w[k] · in[y][x + k − r] (horizontal) or the
// same along columns; outside the grid counts as 0.
void convolve(const std::vector<double>& in, std::vector<double>& out, int width, int height,
              const std::vector<double>& w, bool horizontal) {
  const int r = static_cast<int>(w.size() / 2);
  out.assign(in.size(), 0.0);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      double s = 0.0;
      for (int k = -r; k <= r; ++k) {
        const int xx = horizontal ? x + k : x, yy = horizontal ? y : y + k;
        if (xx < 0 || xx >= width || yy < 0 || yy >= height) continue;
        s += w[k + r] * in[static_cast<std::size_t>(yy) * width + xx];
      }
      out[static_cast<std::size_t>(y) * width + x] = s;
    }
  }
}

std::vector<double> smooth(std::vector<double> grid, int width, int height, const std::vector<double>& w) {
  std::vector<double> tmp;
  convolve(grid, tmp, width, height, w, true);
  convolve(tmp, grid, width, height, w, false);
  return grid;
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
    const std::vector<double> c = smooth(std::vector<double>(a.count.begin(), a.count.end()), a.width, a.height, w);
    for (std::size_t i = 0; i < n; ++i) out.values[i] = c[i] > 0.0 ? static_cast<float>(c[i]) : nan;
    return out;
  }
  if (!a.with_value)
    throw invalid_argument("value", std::string("the aggregate holds no values to average for '") + to_string(value) + "'");
  std::vector<double> sums(n);
  for (std::size_t i = 0; i < n; ++i) sums[i] = static_cast<double>(a.value_sum[i]) / kValueScale;
  const std::vector<double> s = smooth(std::move(sums), a.width, a.height, w);
  const std::vector<double> c =
      smooth(std::vector<double>(a.value_count.begin(), a.value_count.end()), a.width, a.height, w);
  for (std::size_t i = 0; i < n; ++i) out.values[i] = c[i] > 0.0 ? static_cast<float>(s[i] / c[i]) : nan;
  return out;
}

}  // namespace trailscope::density
