// Medial axis transform of one layer (medial.hpp).
//
// 1. Exact squared distance D and feature transform to the outside, on the layer padded by one outside
//    pixel so that the image edge is boundary (edt.cpp).
// 2. The axis: inside pixels whose lattice disk no 8-neighbour's disk contains (exact test, below).
//    Their disks cover the layer: from any pixel, following containing neighbours ends on the axis
//    (containment is transitive and D grows strictly along the way). A neighbourhood of 8 cannot see
//    every containment, so a few non-maximal pixels stay; simplification removes them.
// 3. Importance rho (AFMM boundary collapse on the traced boundary, boundary.cpp) and salience
//    rho / sqrt(D) (saliency skeletons) on the axis, the simplification measure.
#include "dmd/mat.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>
#include <vector>

#include "dmd/boundary.hpp"
#include "dmd/edt.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::dmd::detail {
namespace {

constexpr int kDx8[8] = {1, -1, 0, 0, 1, 1, -1, -1};
constexpr int kDy8[8] = {0, 0, 1, -1, 1, -1, 1, -1};

// Exact containment of neighbouring lattice disks. With q = p + e, disk(p) = {p + v : |v|^2 < Dp} lies
// in disk(q) iff |v - e|^2 < Dq for all those v, i.e. iff max_v (|v|^2 - 2 v.e) + |e|^2 < Dq. By the
// symmetries of the lattice disk that maximum depends on Dp and on whether e is axial or diagonal only;
// it is computed once per Dp in O(sqrt Dp) (for each column vx of the disk only its extreme rows can
// maximise) and cached. (The continuous test sqrt(Dp) + |e| <= sqrt(Dq) is sufficient but fails for
// almost every pixel off the grid directions.)
class DiskTable {
 public:
  bool contains(std::int64_t dq, std::int64_t dp, bool diagonal) {
    if (dq <= dp) return false;  // a lattice disk holds no other of its size or larger
    const Maxima& m = maxima(dp);
    return (diagonal ? m.diagonal + 2 : m.axial + 1) < dq;
  }

 private:
  struct Maxima {
    std::int64_t axial = kUnset, diagonal = kUnset;
  };
  static constexpr std::int64_t kUnset = std::numeric_limits<std::int64_t>::min();
  // Radii below 512 px (the usual case) in a flat table, larger ones in a map: entries are filled
  // only for the D that occur, so memory and time follow the image, not the largest possible D.
  static constexpr std::int64_t kFlat = std::int64_t(1) << 18;

  const Maxima& maxima(std::int64_t d) {
    Maxima* m = nullptr;
    if (d < kFlat) {
      if (static_cast<std::size_t>(d) >= flat_.size())
        flat_.resize(std::max<std::size_t>(d + 1, flat_.size() * 2));
      m = &flat_[d];
    } else {
      m = &large_[d];
    }
    if (m->axial == kUnset) *m = compute(d);
    return *m;
  }

  static Maxima compute(std::int64_t d) {
    Maxima m;
    const auto r = static_cast<std::int64_t>(std::sqrt(double(d)));
    for (std::int64_t vx = -r - 1; vx <= r + 1; ++vx) {
      const std::int64_t rest = d - 1 - vx * vx;  // vy^2 <= rest, i.e. |v|^2 < d
      if (rest < 0) continue;
      std::int64_t vy = static_cast<std::int64_t>(std::sqrt(double(rest)));
      while (vy * vy > rest) --vy;
      while ((vy + 1) * (vy + 1) <= rest) ++vy;
      m.axial = std::max(m.axial, vx * vx - 2 * vx + vy * vy);                 // e = (1, 0), v = (vx, +-vy)
      m.diagonal = std::max(m.diagonal, vx * vx - 2 * vx + vy * vy + 2 * vy);  // e = (1, 1), v = (vx, -vy)
    }
    return m;
  }

  std::vector<Maxima> flat_;
  std::unordered_map<std::int64_t, Maxima> large_;
};

}  // namespace

MatWork compute_mat(const BinaryImage& layer) {
  if (layer.width < 1 || layer.height < 1 || layer.width > 32765 || layer.height > 32765 ||
      layer.pixels.size() != static_cast<std::size_t>(layer.width) * layer.height)
    throw invalid_argument("layer",
                           "layer must be a non-empty binary image of at most 32765 px a side with "
                           "width * height pixels");
  const int w = layer.width, h = layer.height, pw = w + 2, ph = h + 2;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  auto pad = [pw](int x, int y) { return static_cast<std::size_t>(y + 1) * pw + x + 1; };

  // 1. transforms
  std::vector<std::uint8_t> outside(static_cast<std::size_t>(pw) * ph, 1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) outside[pad(x, y)] = layer.at(x, y) ? 0 : 1;
  std::vector<std::int32_t> d2, feature;
  distance_transform(outside.data(), pw, ph, d2, &feature);

  // 2. the axis
  MatWork m;
  m.w = w;
  m.h = h;
  m.mat_r2.assign(n, 0);
  m.salience.assign(n, 0.f);
  thread_local DiskTable table;  // a pure function of D: shared by all layers of a thread
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::int64_t dp = d2[pad(x, y)];
      if (dp == 0) continue;
      bool maximal = true;
      for (int k = 0; k < 8 && maximal; ++k)
        maximal = !table.contains(d2[pad(x + kDx8[k], y + kDy8[k])], dp, k >= 4);
      if (maximal) {
        m.mat_r2[static_cast<std::size_t>(y) * w + x] = static_cast<std::int32_t>(dp);
        ++m.mat_pixels;
      }
    }

  // 3. importance, needed on the axis only. The feature point of an inside pixel p is an outside pixel
  // s; its boundary position is that of the inside 4-neighbour of s nearest to p (s is always
  // 4-adjacent to an inside pixel, or a pixel one step nearer to p would be nearer and outside).
  const BoundaryParam b = trace_boundary(layer);
  struct Position {
    std::int32_t contour = -1;
    float arc = 0;
  };
  auto position = [&](int x, int y) {
    Position best_pos;
    const std::int32_t s = feature[pad(x, y)];
    const int sx = s % pw - 1, sy = s / pw - 1;  // image coordinates, -1 or w / h on the pad
    std::int64_t best = std::numeric_limits<std::int64_t>::max();
    for (int k = 0; k < 4; ++k) {
      const int nx = sx + kDx8[k], ny = sy + kDy8[k];
      if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
      const std::size_t ni = static_cast<std::size_t>(ny) * w + nx;
      if (!layer.pixels[ni] || b.contour[ni] < 0) continue;
      const std::int64_t d = std::int64_t(nx - x) * (nx - x) + std::int64_t(ny - y) * (ny - y);
      if (d < best) {
        best = d;
        best_pos = {b.contour[ni], b.arc[ni]};
      }
    }
    return best_pos;
  };
  // rho(p): the most boundary between p's feature point and an 8-neighbour's (8 rather than AFMM's 4
  // so that the diagonal feature jumps of thin diagonal structures count too); salience rho / sqrt(D).
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * w + x;
      if (m.mat_r2[i] == 0) continue;
      const Position p = position(x, y);
      float rho = 0;
      for (int k = 0; k < 8; ++k) {
        const int nx = x + kDx8[k], ny = y + kDy8[k];
        if (nx < 0 || ny < 0 || nx >= w || ny >= h || !layer.at(nx, ny)) continue;
        const Position q = position(nx, ny);
        rho = std::max(rho, boundary_distance(b, p.contour, p.arc, q.contour, q.arc));
      }
      m.salience[i] = rho / std::sqrt(static_cast<float>(m.mat_r2[i]));
    }
  return m;
}

}  // namespace trailscope::dmd::detail
