#pragma once
// Host code that the C++ references (compute/src/projection/*.cpp) and the OpenCL paths
// (compute/src/projection/projection_ocl.cpp) share: seeded random numbers, the block eigen-solver of MDS,
// the Barnes-Hut quadtree of t-SNE, the t-SNE optimiser loop, and sign normalisation. Sharing them is what
// makes a reference-versus-OpenCL test compare the device products and nothing else.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/rng.hpp"
#include "trailscope/core/progress.hpp"
#include "trailscope/projection/projection.hpp"

namespace trailscope::projection::detail {

/// splitmix64 (core/rng.hpp) started at seed ^ kGolden, so a seed gives the same projection everywhere.
class Rng : public rng::SplitMix64 {
 public:
  explicit Rng(std::uint64_t seed) : SplitMix64(seed ^ rng::kGolden) {}
  std::size_t below(std::size_t n) { return static_cast<std::size_t>(uniform() * static_cast<double>(n)); }
  double normal() {  ///< Box–Muller
    const double u = 1.0 - uniform(), v = uniform();
    return std::sqrt(-2.0 * std::log(u)) * std::cos(6.283185307179586 * v);
  }
};

/// k distinct indices of [0, n), ascending (partial Fisher–Yates).
std::vector<std::size_t> sample_indices(std::size_t n, std::size_t k, std::uint64_t seed);

/// Flips each column of an n×2 row-major layout so that its largest-magnitude entry (first on ties) is
/// positive: eigenvectors have no sign of their own.
void normalize_signs(std::vector<double>& xy, std::size_t n);

/// The two leading eigenpairs of a symmetric n×n operator given by `apply` (V → B·V for an n×p
/// row-major block), by subspace iteration with Rayleigh–Ritz on p = min(n, 6) vectors until the
/// residual ‖B·v − θ·v‖ of both pairs is ≤ tol·|θ_1| (or max_iter). Returns false if it did not
/// converge (the best pairs are still returned).
struct TopEigen {
  double lambda[2] = {0, 0};
  std::vector<double> v;  ///< n × 2 row-major, orthonormal columns
  int iterations = 0;
  bool converged = false;
};
using BlockApply = std::function<void(const std::vector<double>& v, int p, std::vector<double>& out)>;
TopEigen top_eigen(std::size_t n, const BlockApply& apply, std::uint64_t seed, double tol, int max_iter,
                   const CancelToken* cancel);

/// Landmark MDS: from the L×L squared landmark distances (row-major, double), the embedding matrix
/// (L × 2: v_k / √λ_k, λ_k > 0) and the column means δ̄ of the squared distances; then each point's
/// coordinates are −½·Σ_j (δ_aj − δ̄_j)·pinv[j][k].
struct LandmarkMap {
  std::vector<double> pinv;  ///< L × 2
  std::vector<double> mean;  ///< L
};
LandmarkMap landmark_map(const std::vector<double>& d2, std::size_t L);

/// MDS subspace-iteration settings shared by both paths. The device accumulates B·V in float, whose
/// rounding (≈1e-7·√N relative) bounds the reachable residual; 1e-5 is above that floor and gives
/// coordinates to ~1e-5 of the layout's extent when the eigen-gap is not tiny.
inline constexpr double kEigenTol = 1e-5;
inline constexpr int kEigenMaxIter = 1000;

/// Barnes-Hut quadtree over 2D points, flattened for the device: node k has centre of mass
/// (node[4k], node[4k+1]), cell side node[4k+2] and point count node[4k+3]; child[k] is the first of its
/// 4 contiguous children or −1 for a leaf; point[k] is a point of a leaf (−1 if empty). Leaves hold one
/// point, except at kMaxDepth where coincident (or nearly) points share a leaf.
struct QuadTree {
  static constexpr int kMaxDepth = 30;
  static constexpr int kStack = 4 * kMaxDepth + 8;  ///< traversal stack bound (≤ 3 per level + 1)
  std::vector<float> node;
  std::vector<std::int32_t> child, point;
  void build(const std::vector<double>& y, std::size_t n);

 private:
  std::vector<double> cx_, cy_, half_, sx_, sy_;  // build-time cell centre, half side, coordinate sums
  std::vector<std::int32_t> cnt_;
  std::int32_t add_children(std::int32_t k);
};

/// The points' indices sorted along a Morton (Z-order) curve of their positions (16 bits per axis over
/// the bounding box): the traversal order of the Barnes-Hut kernel.
void morton_order(const std::vector<double>& y, std::size_t n, std::vector<std::int32_t>& order);

/// Repulsion of point i from the tree: adds Σ m·w²·(y_i − c) to f and Σ m·w to z, w = 1/(1 + |y_i − c|²),
/// opening a cell unless it is a leaf or side² < θ²·|y_i − c|². The kernel tsne_repulse_bh does the same.
void bh_repulse(const QuadTree& t, std::int32_t i, double yx, double yy, double theta2, double& fx,
                double& fy, double& z);

/// The t-SNE optimiser shared by both paths (openTSNE's gradient descent): `grad(y, exaggeration, g)`
/// writes the gradient (2n) at y. Updates y in place, re-centred each step (translation leaves the
/// gradient unchanged and keeps the float device coordinates small).
void tsne_optimize(std::vector<double>& y, std::size_t n, const TsneOptions& o,
                   const std::function<void(const std::vector<double>&, double, std::vector<double>&)>& grad);

/// The attraction Σ_j p_ij·w_ij·(y_i − y_j) of every point (rows × 2), in double.
void tsne_attraction(const Affinities& P, const std::vector<double>& y, std::vector<double>& attr);

/// The t-SNE gradient exaggeration·attr_i − rep_i / Z from the attraction (2 values a point) and the
/// repulsion terms (`stride` values a point: the two force sums, then point i's share of Z), every path's
/// last step. Z is summed in double and floored, so that a layout of coincident points stays finite.
template <typename A, typename R>
void tsne_combine(const A* attr, const R* rep, std::size_t stride, std::size_t n, double exaggeration,
                  std::vector<double>& g) {
  double z = 0;
  for (std::size_t i = 0; i < n; ++i) z += rep[stride * i + 2];
  z = std::max(z, 1e-300);
  g.resize(2 * n);
  for (std::size_t i = 0; i < n; ++i) {
    g[2 * i] = exaggeration * attr[2 * i] - rep[stride * i] / z;
    g[2 * i + 1] = exaggeration * attr[2 * i + 1] - rep[stride * i + 1] / z;
  }
}

/// max(N/12, 200) unless set.
double tsne_learning_rate(std::size_t n, const TsneOptions& o);

/// PCA initialisation of t-SNE: the PCA scores scaled so that the first coordinate has std 1e-4
/// (openTSNE); seeded Gaussian of std 1e-4 when the data has no variance.
std::vector<double> tsne_init(const Table& t, std::uint64_t seed);

/// Force Scheme start: seeded uniform in [0, max δ]², centred (a centred start stays centred).
std::vector<double> force_init(std::size_t n, double max_delta, std::uint64_t seed);

/// Number of LAMP control points: ⌈√N⌉, at least 3 (and ≤ N).
std::size_t lamp_controls(std::size_t n);

/// Throws Error(cancelled) when asked to.
inline void check_cancel(const CancelToken* c) {
  if (c) c->throw_if_cancelled();
}

}  // namespace trailscope::projection::detail
