#pragma once
// Shared helpers of the projection tests: seeded synthetic tables and an environment guard.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "test_support.hpp"
#include "trailscope/projection/table.hpp"

namespace trailscope::projection::test {

using trailscope::test::ScopedEnv;

/// `clusters` isotropic Gaussian clusters (std 1) in `dims` dimensions whose centres are drawn
/// uniformly in [0, separation]^dims; label = cluster of each row.
inline Table gaussian_clusters(std::size_t rows, std::size_t dims, int clusters, double separation,
                               std::uint64_t seed, std::vector<int>* labels = nullptr) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto normal = [&] {
    const double a = 1.0 - u(rng), b = u(rng);
    return std::sqrt(-2.0 * std::log(a)) * std::cos(6.283185307179586 * b);
  };
  std::vector<double> centres(static_cast<std::size_t>(clusters) * dims);
  for (double& c : centres) c = u(rng) * separation;
  Table t;
  t.rows = rows, t.cols = dims;
  t.values.resize(rows * dims);
  if (labels) labels->resize(rows);
  for (std::size_t r = 0; r < rows; ++r) {
    const int c = static_cast<int>(r % static_cast<std::size_t>(clusters));
    if (labels) (*labels)[r] = c;
    for (std::size_t d = 0; d < dims; ++d)
      t.values[r * dims + d] = static_cast<float>(centres[static_cast<std::size_t>(c) * dims + d] + normal());
  }
  for (std::size_t d = 0; d < dims; ++d) t.columns.push_back("x" + std::to_string(d));
  return t;
}

/// Euclidean distance of rows i, j of an n × 2 layout.
inline double dist2d(const std::vector<double>& xy, std::size_t i, std::size_t j) {
  return std::hypot(xy[2 * i] - xy[2 * j], xy[2 * i + 1] - xy[2 * j + 1]);
}

/// Largest |a − b| over the entries, divided by the largest |b|: agreement relative to the layout's size.
inline double rel_diff(const std::vector<double>& a, const std::vector<double>& b) {
  double m = 0, s = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    m = std::max(m, std::abs(a[i] - b[i])), s = std::max(s, std::abs(b[i]));
  return s > 0 ? m / s : m;
}

}  // namespace trailscope::projection::test
