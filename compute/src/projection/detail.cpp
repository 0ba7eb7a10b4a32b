// Shared host code of the projections (see detail.hpp).
#include "projection/detail.hpp"

#include <Eigen/Dense>

#include <numeric>

#include "trailscope/core/error.hpp"

namespace trailscope::projection::detail {

std::vector<std::size_t> sample_indices(std::size_t n, std::size_t k, std::uint64_t seed) {
  k = std::min(k, n);
  std::vector<std::size_t> all(n);
  std::iota(all.begin(), all.end(), std::size_t{0});
  Rng rng(seed);
  for (std::size_t i = 0; i < k; ++i) std::swap(all[i], all[i + rng.below(n - i)]);
  all.resize(k);
  std::sort(all.begin(), all.end());
  return all;
}

void normalize_signs(std::vector<double>& xy, std::size_t n) {
  for (int c = 0; c < 2; ++c) {
    double best = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (std::abs(xy[2 * i + c]) > std::abs(best)) best = xy[2 * i + c];
    if (best < 0)
      for (std::size_t i = 0; i < n; ++i) xy[2 * i + c] = -xy[2 * i + c];
  }
}

namespace {
// Orthonormalises the p columns of an n×p row-major block in place (modified Gram–Schmidt, twice for
// stability); a column that vanishes is replaced by a seeded random one.
void orthonormalize(std::vector<double>& v, std::size_t n, int p, Rng& rng) {
  for (int c = 0; c < p; ++c) {
    for (int pass = 0; pass < 2; ++pass)
      for (int b = 0; b < c; ++b) {
        double dot = 0;
        for (std::size_t i = 0; i < n; ++i) dot += v[i * p + c] * v[i * p + b];
        for (std::size_t i = 0; i < n; ++i) v[i * p + c] -= dot * v[i * p + b];
      }
    double norm = 0;
    for (std::size_t i = 0; i < n; ++i) norm += v[i * p + c] * v[i * p + c];
    norm = std::sqrt(norm);
    if (norm < 1e-300) {
      for (std::size_t i = 0; i < n; ++i) v[i * p + c] = rng.normal();
      --c;  // orthogonalise the replacement again
      continue;
    }
    for (std::size_t i = 0; i < n; ++i) v[i * p + c] /= norm;
  }
}
}  // namespace

TopEigen top_eigen(std::size_t n, const BlockApply& apply, std::uint64_t seed, double tol, int max_iter,
                   const CancelToken* cancel) {
  const int p = static_cast<int>(std::min<std::size_t>(n, 6));
  Rng rng(seed);
  std::vector<double> v(n * p), w;
  for (double& x : v) x = rng.normal();
  orthonormalize(v, n, p, rng);
  TopEigen out;
  out.v.assign(n * 2, 0.0);
  for (int it = 1; it <= max_iter; ++it) {
    check_cancel(cancel);
    apply(v, p, w);  // w = B·V
    Eigen::MatrixXd h(p, p);
    for (int a = 0; a < p; ++a)
      for (int b = 0; b < p; ++b) {
        double s = 0;
        for (std::size_t i = 0; i < n; ++i) s += v[i * p + a] * w[i * p + b];
        h(a, b) = s;
      }
    h = 0.5 * (h + h.transpose());
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(h);
    // Descending by value: B is positive semidefinite for Euclidean input, so the leading pairs are
    // the largest ones.
    std::vector<int> order(p);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
              [&](int a, int b) { return es.eigenvalues()(a) > es.eigenvalues()(b); });
    // Ritz vectors x = V·s and B·x = W·s; residuals of the two leading pairs.
    std::vector<double> nv(n * p, 0.0);
    double res[2] = {0, 0};
    for (int c = 0; c < p; ++c) {
      const auto s = es.eigenvectors().col(order[c]);
      const double theta = es.eigenvalues()(order[c]);
      double r2 = 0;
      for (std::size_t i = 0; i < n; ++i) {
        double x = 0, bx = 0;
        for (int b = 0; b < p; ++b) x += v[i * p + b] * s(b), bx += w[i * p + b] * s(b);
        if (c < 2) out.v[i * 2 + c] = x, r2 += (bx - theta * x) * (bx - theta * x);
        nv[i * p + c] = bx;  // the next block: B·(Ritz vectors)
      }
      if (c < 2) res[c] = std::sqrt(r2), out.lambda[c] = theta;
    }
    out.iterations = it;
    const double scale = std::max(std::abs(out.lambda[0]), 1e-300);
    if (res[0] <= tol * scale && (p < 2 || res[1] <= tol * scale)) {
      out.converged = true;
      break;
    }
    if (out.lambda[0] <= 1e-300) {  // B = 0: every vector is an eigenvector of 0
      out.converged = true;
      break;
    }
    v.swap(nv);
    orthonormalize(v, n, p, rng);
  }
  if (p < 2) out.lambda[1] = 0;
  return out;
}

LandmarkMap landmark_map(const std::vector<double>& d2, std::size_t L) {
  Eigen::MatrixXd b(L, L);
  std::vector<double> row(L, 0.0);
  double grand = 0;
  for (std::size_t i = 0; i < L; ++i) {
    for (std::size_t j = 0; j < L; ++j) row[i] += d2[i * L + j];
    grand += row[i];
    row[i] /= static_cast<double>(L);
  }
  grand /= static_cast<double>(L) * static_cast<double>(L);
  for (std::size_t i = 0; i < L; ++i)
    for (std::size_t j = 0; j < L; ++j) b(i, j) = -0.5 * (d2[i * L + j] - row[i] - row[j] + grand);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(b);
  LandmarkMap m;
  m.pinv.assign(L * 2, 0.0);
  m.mean = row;  // symmetric: column means = row means
  const double top = std::max(es.eigenvalues()(L - 1), 0.0);
  for (int c = 0; c < 2 && c < static_cast<int>(L); ++c) {
    const Eigen::Index col = static_cast<Eigen::Index>(L) - 1 - c;
    const double lambda = es.eigenvalues()(col);
    // A non-positive (or negligible) eigenvalue carries no Euclidean dimension: that axis stays 0.
    if (lambda <= 1e-12 * top || lambda <= 0) continue;
    for (std::size_t j = 0; j < L; ++j) m.pinv[j * 2 + c] = es.eigenvectors()(j, col) / std::sqrt(lambda);
  }
  return m;
}

// --- Barnes-Hut quadtree ----------------------------------------------------------------------------

std::int32_t QuadTree::add_children(std::int32_t k) {
  const auto first = static_cast<std::int32_t>(cx_.size());
  const double h = half_[k] * 0.5;
  for (int q = 0; q < 4; ++q) {
    cx_.push_back(cx_[k] + ((q & 1) ? h : -h));
    cy_.push_back(cy_[k] + ((q & 2) ? h : -h));
    half_.push_back(h);
    sx_.push_back(0), sy_.push_back(0), cnt_.push_back(0);
    child.push_back(-1), point.push_back(-1);
  }
  child[k] = first;
  return first;
}

void QuadTree::build(const std::vector<double>& y, std::size_t n) {
  cx_.clear(), cy_.clear(), half_.clear(), sx_.clear(), sy_.clear(), cnt_.clear();
  child.clear(), point.clear();
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (std::size_t i = 0; i < n; ++i) {
    x0 = std::min(x0, y[2 * i]), x1 = std::max(x1, y[2 * i]);
    y0 = std::min(y0, y[2 * i + 1]), y1 = std::max(y1, y[2 * i + 1]);
  }
  const double side = std::max({x1 - x0, y1 - y0, 1e-30}) * (1 + 1e-9);
  cx_.push_back(0.5 * (x0 + x1)), cy_.push_back(0.5 * (y0 + y1)), half_.push_back(0.5 * side);
  sx_.push_back(0), sy_.push_back(0), cnt_.push_back(0), child.push_back(-1), point.push_back(-1);
  for (std::size_t i = 0; i < n; ++i) {
    const double px = y[2 * i], py = y[2 * i + 1];
    std::int32_t k = 0;
    for (int depth = 0;; ++depth) {
      sx_[k] += px, sy_[k] += py, ++cnt_[k];
      if (child[k] < 0) {
        if (cnt_[k] == 1) {  // was empty
          point[k] = static_cast<std::int32_t>(i);
          break;
        }
        if (depth >= kMaxDepth) break;  // coincident points share this leaf
        // Split: push the resident point one level down, then keep descending with the new one.
        const std::int32_t old = point[k];
        point[k] = -1;
        const std::int32_t first = add_children(k);
        const double ox = y[2 * static_cast<std::size_t>(old)], oy = y[2 * static_cast<std::size_t>(old) + 1];
        const std::int32_t oc = first + (ox >= cx_[k] ? 1 : 0) + (oy >= cy_[k] ? 2 : 0);
        sx_[oc] += ox, sy_[oc] += oy, cnt_[oc] = 1, point[oc] = old;
      }
      k = child[k] + (px >= cx_[k] ? 1 : 0) + (py >= cy_[k] ? 2 : 0);
    }
  }
  const std::size_t m = cx_.size();
  node.resize(4 * m);
  for (std::size_t k = 0; k < m; ++k) {
    const double c = cnt_[k];
    node[4 * k] = static_cast<float>(c > 0 ? sx_[k] / c : cx_[k]);
    node[4 * k + 1] = static_cast<float>(c > 0 ? sy_[k] / c : cy_[k]);
    node[4 * k + 2] = static_cast<float>(2 * half_[k]);
    node[4 * k + 3] = static_cast<float>(c);
  }
}

void morton_order(const std::vector<double>& y, std::size_t n, std::vector<std::int32_t>& order) {
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (std::size_t i = 0; i < n; ++i) {
    x0 = std::min(x0, y[2 * i]), x1 = std::max(x1, y[2 * i]);
    y0 = std::min(y0, y[2 * i + 1]), y1 = std::max(y1, y[2 * i + 1]);
  }
  const double sx = 65535.0 / std::max(x1 - x0, 1e-300), sy = 65535.0 / std::max(y1 - y0, 1e-300);
  const auto spread = [](std::uint32_t v) {  // 16 bits → every other bit of 32
    v = (v | (v << 8)) & 0x00FF00FFu;
    v = (v | (v << 4)) & 0x0F0F0F0Fu;
    v = (v | (v << 2)) & 0x33333333u;
    return (v | (v << 1)) & 0x55555555u;
  };
  std::vector<std::uint64_t> key(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto qx = static_cast<std::uint32_t>((y[2 * i] - x0) * sx);
    const auto qy = static_cast<std::uint32_t>((y[2 * i + 1] - y0) * sy);
    key[i] = (static_cast<std::uint64_t>(spread(qx) | (spread(qy) << 1)) << 32) | i;  // index breaks ties
  }
  std::sort(key.begin(), key.end());
  order.resize(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = static_cast<std::int32_t>(key[i] & 0xFFFFFFFFu);
}

void bh_repulse(const QuadTree& t, std::int32_t i, double yx, double yy, double theta2, double& fx,
                double& fy, double& z) {
  std::int32_t stack[QuadTree::kStack];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const std::int32_t k = stack[--top];
    const double c = t.node[4 * k + 3];
    if (c <= 0) continue;
    const double dx = yx - t.node[4 * k], dy = yy - t.node[4 * k + 1];
    const double d2 = dx * dx + dy * dy;
    double m = c;
    if (t.child[k] < 0) {
      if (c == 1 && t.point[k] == i) continue;  // itself
      if (c > 1 && d2 == 0) m = c - 1;          // a shared leaf holding i: all but i
    } else {
      const double side = t.node[4 * k + 2];
      if (side * side >= theta2 * d2) {
        for (int q = 3; q >= 0; --q) stack[top++] = t.child[k] + q;
        continue;
      }
    }
    const double w = 1.0 / (1.0 + d2);
    z += m * w;
    fx += m * w * w * dx, fy += m * w * w * dy;
  }
}

// --- t-SNE optimiser ----------------------------------------------------------------------------------

double tsne_learning_rate(std::size_t n, const TsneOptions& o) {
  return o.learning_rate > 0 ? o.learning_rate : std::max(static_cast<double>(n) / 12.0, 200.0);
}

void tsne_optimize(
    std::vector<double>& y, std::size_t n, const TsneOptions& o,
    const std::function<void(const std::vector<double>&, double, std::vector<double>&)>& grad) {
  const double lr = tsne_learning_rate(n, o);
  std::vector<double> update(2 * n, 0.0), gains(2 * n, 1.0), g(2 * n, 0.0);
  const int total = o.exaggeration_iterations + o.iterations;
  const auto sgn = [](double v) { return (v > 0) - (v < 0); };
  for (int it = 0; it < total; ++it) {
    check_cancel(o.cancel);
    const bool early = it < o.exaggeration_iterations;
    const double exaggeration = early ? o.exaggeration : 1.0;
    const double momentum = early ? 0.5 : 0.8;
    grad(y, exaggeration, g);
    double mx = 0, my = 0;
    for (std::size_t c = 0; c < 2 * n; ++c) {
      // openTSNE: the gain grows where the step keeps its direction (update and gradient of opposite
      // signs, since update ∝ −gradient) and shrinks where it oscillates.
      gains[c] = sgn(update[c]) != sgn(g[c]) ? gains[c] + 0.2 : gains[c] * 0.8;
      gains[c] = std::max(gains[c], 0.01);
      update[c] = momentum * update[c] - lr * gains[c] * g[c];
      y[c] += update[c];
    }
    for (std::size_t i = 0; i < n; ++i) mx += y[2 * i], my += y[2 * i + 1];
    mx /= static_cast<double>(n), my /= static_cast<double>(n);
    for (std::size_t i = 0; i < n; ++i) y[2 * i] -= mx, y[2 * i + 1] -= my;
    if (o.progress && (it % 10 == 0 || it + 1 == total))
      o.progress(0.2 + 0.8 * static_cast<double>(it + 1) / static_cast<double>(total),
                 early ? "early exaggeration" : "optimise");
  }
}

std::vector<double> tsne_init(const Table& t, std::uint64_t seed) {
  const Embedding e = pca_ref(t);
  std::vector<double> y = e.xy;
  const std::size_t n = t.rows;
  double mean = 0, var = 0;
  for (std::size_t i = 0; i < n; ++i) mean += y[2 * i];
  mean /= static_cast<double>(n);
  for (std::size_t i = 0; i < n; ++i) var += (y[2 * i] - mean) * (y[2 * i] - mean);
  const double sd = std::sqrt(var / static_cast<double>(n));
  if (sd > 0) {
    for (double& v : y) v *= 1e-4 / sd;
  } else {
    Rng rng(seed);
    for (double& v : y) v = 1e-4 * rng.normal();
  }
  return y;
}

std::vector<double> force_init(std::size_t n, double max_delta, std::uint64_t seed) {
  Rng rng(seed);
  std::vector<double> y(2 * n);
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < n; ++i) {
    y[2 * i] = rng.uniform() * max_delta, y[2 * i + 1] = rng.uniform() * max_delta;
    mx += y[2 * i], my += y[2 * i + 1];
  }
  mx /= static_cast<double>(n), my /= static_cast<double>(n);
  for (std::size_t i = 0; i < n; ++i) y[2 * i] -= mx, y[2 * i + 1] -= my;
  return y;
}

std::size_t lamp_controls(std::size_t n) {
  const auto c = static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(n))));
  return std::min(n, std::max<std::size_t>(c, 3));
}

}  // namespace trailscope::projection::detail
