#pragma once
// Polylines: the one geometry type of bundling. A graph edge is a 2-point polyline, a trail has many
// points. Points of all polylines are stored flat (structure of arrays) with an offsets table, the layout
// the OpenCL kernels read.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace trailscope::bundling {

/// Polylines in some plane coordinate system (source units: graph coordinates, Web Mercator units,
/// bundle pixels; the owner says which). Polyline i is points offsets[i] .. offsets[i+1]−1.
struct Polylines {
  std::vector<double> x, y;
  std::vector<std::uint32_t> offsets{0};  ///< size() + 1 entries, offsets[0] = 0

  std::size_t size() const { return offsets.size() - 1; }
  std::size_t points() const { return x.size(); }
  std::size_t begin(std::size_t i) const { return offsets[i]; }
  std::size_t end(std::size_t i) const { return offsets[i + 1]; }
  /// Appends one polyline (xs and ys of equal length).
  void add(std::span<const double> xs, std::span<const double> ys) {
    x.insert(x.end(), xs.begin(), xs.end());
    y.insert(y.end(), ys.begin(), ys.end());
    offsets.push_back(static_cast<std::uint32_t>(x.size()));
  }
  /// Appends the straight edge (x0, y0) → (x1, y1).
  void add_edge(double x0, double y0, double x1, double y1) {
    x.push_back(x0), y.push_back(y0), x.push_back(x1), y.push_back(y1);
    offsets.push_back(static_cast<std::uint32_t>(x.size()));
  }
};

}  // namespace trailscope::bundling
