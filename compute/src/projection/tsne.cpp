// t-SNE: exact kNN (GEMM), per-point perplexity calibration, symmetric sparse P, and gradient descent
// whose attraction (sparse P) and repulsion (exact, Barnes-Hut or FFT interpolation, tsne_fft.cpp) run on
// the device in the OpenCL path.
#include <Eigen/Dense>
#include <tbb/parallel_for.h>

#include <chrono>
#include <numeric>

#include "ocl/dispatch.hpp"
#include "projection/projection_ocl.hpp"
#include "projection/tsne_fft_ocl.hpp"
#include "projection/detail.hpp"
#include "projection/tsne_fft.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/projection/projection.hpp"

namespace trailscope::projection {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

void check_k(const Table& t, int k) {
  if (k < 1 || static_cast<std::size_t>(k) >= t.rows || k > 300)
    throw invalid_argument("k", "k must be in [1, min(rows − 1, 300)], not " + std::to_string(k));
}

void check_tsne(const Table& t, const TsneOptions& o) {
  validate_table(t);
  if (t.rows > limits::kMaxTsneRows)
    throw Error(Error::Kind::payload_too_large, "table",
                "t-SNE takes at most " + std::to_string(limits::kMaxTsneRows) + " rows, not " +
                    std::to_string(t.rows));
  if (!(o.perplexity >= 1.0) || !(o.perplexity <= limits::kMaxPerplexity))
    throw invalid_argument("perplexity", "perplexity must be in [1, " +
                                             std::to_string(static_cast<int>(limits::kMaxPerplexity)) +
                                             "], not " + std::to_string(o.perplexity));
  if (3.0 * o.perplexity > static_cast<double>(t.rows - 1))
    throw invalid_argument("perplexity", "perplexity " + std::to_string(o.perplexity) + " needs at least " +
                                             std::to_string(static_cast<long>(3.0 * o.perplexity) + 1) +
                                             " rows (3·perplexity neighbours); the table has " +
                                             std::to_string(t.rows));
  const auto iters_ok = [](int v) { return v >= 0 && v <= limits::kMaxProjectionIterations; };
  if (!iters_ok(o.iterations) || !iters_ok(o.exaggeration_iterations))
    throw invalid_argument(
        "iterations", "iterations must be in [0, " + std::to_string(limits::kMaxProjectionIterations) + "]");
  if (!(o.exaggeration >= 1.0) || !(o.exaggeration <= 1000.0))
    throw invalid_argument("exaggeration", "exaggeration must be in [1, 1000]");
  if (!(o.learning_rate >= 0.0) || !std::isfinite(o.learning_rate))
    throw invalid_argument("learning_rate", "learning_rate must be ≥ 0 (0 = automatic)");
  if (!(o.theta >= 0.0) || !(o.theta <= 1.0)) throw invalid_argument("theta", "theta must be in [0, 1]");
  detail::check_fft_options(o.fft);
}

int neighbours(const Table& t, double perplexity) {
  return static_cast<int>(std::min<double>(static_cast<double>(t.rows - 1), std::floor(3.0 * perplexity)));
}

}  // namespace

Knn knn_ref(const Table& t, int k) {
  check_k(t, k);
  const std::size_t n = t.rows, d = t.cols;
  Knn out;
  out.rows = n, out.k = k;
  out.idx.resize(n * k), out.sqdist.resize(n * k);
  // Candidates from |x|² + |y|² − 2·x·y by a float GEMM per block of rows (the O(N²·D) part, ~20× faster
  // than the pairwise loop), then the exact double distance of every candidate within the GEMM's
  // rounding bound of the k-th: the result is the exact (distance, index) order of the pairwise loop.
  using RowMat = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const Eigen::Map<const RowMat> x(t.values.data(), static_cast<Eigen::Index>(n),
                                   static_cast<Eigen::Index>(d));
  const Eigen::VectorXf sq = x.rowwise().squaredNorm();
  double max_sq = 0;
  for (std::size_t i = 0; i < n; ++i) {
    double s = 0;
    for (std::size_t c = 0; c < d; ++c) s += static_cast<double>(t.row(i)[c]) * t.row(i)[c];
    max_sq = std::max(max_sq, s);
  }
  if (!(max_sq < 1e30)) {  // |x|² would overflow the float GEMM: the plain pairwise loop instead
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
      std::vector<std::pair<double, std::int32_t>> all;
      all.reserve(n - 1);
      for (std::size_t j = 0; j < n; ++j) {
        if (j == i) continue;
        double s = 0;
        for (std::size_t c = 0; c < d; ++c) {
          const double v = static_cast<double>(t.row(i)[c]) - t.row(j)[c];
          s += v * v;
        }
        all.emplace_back(s, static_cast<std::int32_t>(j));
      }
      std::partial_sort(all.begin(), all.begin() + k, all.end());
      for (int a = 0; a < k; ++a)
        out.idx[i * k + a] = all[a].second, out.sqdist[i * k + a] = static_cast<float>(all[a].first);
    });
    return out;
  }
  const std::size_t block = 128;
  tbb::parallel_for(std::size_t{0}, (n + block - 1) / block, [&](std::size_t b) {
    const std::size_t r0 = b * block, m = std::min(block, n - r0);
    const RowMat g =
        x.middleRows(static_cast<Eigen::Index>(r0), static_cast<Eigen::Index>(m)) * x.transpose();
    std::vector<float> approx(n), heap;
    std::vector<std::pair<double, std::int32_t>> exact;
    for (std::size_t a = 0; a < m; ++a) {
      const std::size_t i = r0 + a;
      const float* gi = g.data() + a * n;
      for (std::size_t j = 0; j < n; ++j) approx[j] = sq[i] + sq[j] - 2.0f * gi[j];
      approx[i] = std::numeric_limits<float>::infinity();
      // The k-th smallest approximate distance: a max-heap of the k smallest so far, which most values
      // fail to enter after the first few hundred (several times faster than nth_element here).
      heap.assign(approx.begin(), approx.begin() + k);
      std::make_heap(heap.begin(), heap.end());
      for (std::size_t j = static_cast<std::size_t>(k); j < n; ++j)
        if (approx[j] < heap.front()) {
          std::pop_heap(heap.begin(), heap.end());
          heap.back() = approx[j];
          std::push_heap(heap.begin(), heap.end());
        }
      // |error| of a float dot product of length d ≤ d·2⁻²⁴·|x||y| (plus the norms' rounding).
      const double bound = heap.front() + 4.0 * static_cast<double>(d + 2) * 0x1.0p-24 * (sq[i] + max_sq);
      exact.clear();
      const float* xi = t.row(i);
      for (std::size_t j = 0; j < n; ++j) {
        if (j == i || approx[j] > bound) continue;
        const float* xj = t.row(j);
        double s = 0;
        for (std::size_t c = 0; c < d; ++c) {
          const double v = static_cast<double>(xi[c]) - xj[c];
          s += v * v;
        }
        exact.emplace_back(s, static_cast<std::int32_t>(j));
      }
      std::partial_sort(exact.begin(), exact.begin() + k, exact.end());  // (distance, index) order
      for (int c = 0; c < k; ++c) {
        out.idx[i * k + c] = exact[c].second;
        out.sqdist[i * k + c] = static_cast<float>(exact[c].first);
      }
    }
  });
  return out;
}

Knn knn(const Table& t, int k, Backend backend) {
  check_k(t, k);
  Knn out;
  ocl::dispatch(
      "projection_knn", backend, ocl::device_is_gpu() && t.rows >= 2000,
      [&]() -> std::string {
        Knn r;
        r.rows = t.rows, r.k = k;
        r.idx.resize(t.rows * k), r.sqdist.resize(t.rows * k);
        if (auto why =
                ocl::projection_knn_ocl(t.values.data(), t.rows, t.cols, k, r.idx.data(), r.sqdist.data());
            !why.empty())
          return why;
        out = std::move(r);
        return {};
      },
      [&] { out = knn_ref(t, k); });
  return out;
}

Affinities tsne_affinities(const Knn& g, double perplexity) {
  const std::size_t n = g.rows;
  const int k = g.k;
  const double target = std::log(perplexity);
  std::vector<double> cond(n * k);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    const float* d = g.sqdist.data() + i * k;
    const double d0 = d[0];  // shift: exp(−β(d − d0)) keeps the largest term 1, no underflow of all
    double beta = 1.0, lo = 0.0, hi = std::numeric_limits<double>::infinity();
    double* p = cond.data() + i * k;
    for (int step = 0; step < 200; ++step) {
      double sum = 0, dsum = 0;
      for (int a = 0; a < k; ++a) {
        p[a] = std::exp(-beta * (d[a] - d0));
        sum += p[a], dsum += (d[a] - d0) * p[a];
      }
      const double h = std::log(sum) + beta * dsum / sum;  // entropy (nats) of the normalised row
      for (int a = 0; a < k; ++a) p[a] /= sum;
      if (std::abs(h - target) < 1e-5) break;
      if (h > target) {  // too flat: sharpen
        lo = beta;
        beta = std::isinf(hi) ? beta * 2 : 0.5 * (beta + hi);
      } else {
        hi = beta;
        beta = 0.5 * (beta + lo);
      }
    }
  });
  // Symmetrise: P = (P_cond + P_condᵀ) / (2N), as CSR with sorted columns.
  std::vector<std::int64_t> count(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i)
    for (int a = 0; a < k; ++a) ++count[i + 1], ++count[static_cast<std::size_t>(g.idx[i * k + a]) + 1];
  std::partial_sum(count.begin(), count.end(), count.begin());
  std::vector<std::int32_t> col(count[n]);
  std::vector<double> val(count[n]);
  std::vector<std::int64_t> fill(count.begin(), count.end() - 1);
  const double norm = 1.0 / (2.0 * static_cast<double>(n));
  for (std::size_t i = 0; i < n; ++i)
    for (int a = 0; a < k; ++a) {
      const std::size_t j = static_cast<std::size_t>(g.idx[i * k + a]);
      const double v = cond[i * k + a] * norm;
      col[fill[i]] = static_cast<std::int32_t>(j), val[fill[i]++] = v;
      col[fill[j]] = static_cast<std::int32_t>(i), val[fill[j]++] = v;
    }
  Affinities P;
  P.rows = n;
  P.row_start.assign(1, 0);
  std::vector<std::pair<std::int32_t, double>> row;
  for (std::size_t i = 0; i < n; ++i) {
    row.clear();
    for (std::int64_t e = count[i]; e < count[i + 1]; ++e) row.emplace_back(col[e], val[e]);
    std::sort(row.begin(), row.end());
    for (std::size_t e = 0; e < row.size(); ++e) {
      if (!P.col.empty() && static_cast<std::int64_t>(P.col.size()) > P.row_start.back() &&
          P.col.back() == row[e].first)
        P.p.back() += row[e].second;  // j is a neighbour of i and i of j
      else
        P.col.push_back(row[e].first), P.p.push_back(row[e].second);
    }
    P.row_start.push_back(static_cast<std::int64_t>(P.col.size()));
  }
  return P;
}

void detail::tsne_attraction(const Affinities& P, const std::vector<double>& y, std::vector<double>& attr) {
  const std::size_t n = P.rows;
  attr.resize(2 * n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    const double yx = y[2 * i], yy = y[2 * i + 1];
    double ax = 0, ay = 0;
    for (std::int64_t e = P.row_start[i]; e < P.row_start[i + 1]; ++e) {
      const std::size_t j = static_cast<std::size_t>(P.col[e]);
      const double dx = yx - y[2 * j], dy = yy - y[2 * j + 1];
      const double w = P.p[e] / (1.0 + dx * dx + dy * dy);
      ax += w * dx, ay += w * dy;
    }
    attr[2 * i] = ax, attr[2 * i + 1] = ay;
  });
}

std::vector<double> tsne_gradient_ref(const Affinities& P, const std::vector<double>& y, double exaggeration,
                                      double theta) {
  const std::size_t n = P.rows;
  std::vector<double> attr, rep(2 * n, 0.0), zpart(n, 0.0);
  detail::tsne_attraction(P, y, attr);
  detail::QuadTree tree;
  if (theta > 0) tree.build(y, n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    const double yx = y[2 * i], yy = y[2 * i + 1];
    double fx = 0, fy = 0, z = 0;
    if (theta > 0) {
      detail::bh_repulse(tree, static_cast<std::int32_t>(i), yx, yy, theta * theta, fx, fy, z);
    } else {
      for (std::size_t j = 0; j < n; ++j) {
        if (j == i) continue;
        const double dx = yx - y[2 * j], dy = yy - y[2 * j + 1];
        const double w = 1.0 / (1.0 + dx * dx + dy * dy);
        z += w, fx += w * w * dx, fy += w * w * dy;
      }
    }
    rep[2 * i] = fx, rep[2 * i + 1] = fy, zpart[i] = z;
  });
  double z = 0;
  for (double v : zpart) z += v;
  z = std::max(z, 1e-300);
  std::vector<double> g(2 * n);
  for (std::size_t c = 0; c < 2 * n; ++c) g[c] = exaggeration * attr[c] - rep[c] / z;
  return g;
}

std::vector<double> tsne_gradient(const Affinities& P, const std::vector<double>& y, double exaggeration,
                                  double theta, Backend backend) {
  if (y.size() != 2 * P.rows) throw invalid_argument("y", "y must hold rows × 2 coordinates");
  std::vector<double> g;
  ocl::dispatch(
      "projection_tsne", backend, ocl::device_is_gpu(),
      [&]() { return ocl::projection_tsne_gradient_ocl(P, y, exaggeration, theta, g); },
      [&] { g = tsne_gradient_ref(P, y, exaggeration, theta); });
  return g;
}

namespace {

TsneRepulsion resolve(std::size_t n, const TsneOptions& o) {
  if (o.repulsion != TsneRepulsion::automatic) return o.repulsion;
  if (n <= limits::kMaxExactTsneRows || o.theta == 0) return TsneRepulsion::exact;
  return TsneRepulsion::fft;
}

const char* variant_name(TsneRepulsion r) {
  switch (r) {
    case TsneRepulsion::exact:
      return "exact";
    case TsneRepulsion::barnes_hut:
      return "barnes-hut";
    default:
      return "fft";
  }
}

Embedding run_tsne(const Table& t, const TsneOptions& o, Backend backend, bool reference) {
  check_tsne(t, o);
  const auto t0 = Clock::now();
  const std::size_t n = t.rows;
  const TsneRepulsion rep = resolve(n, o);
  const double theta = rep == TsneRepulsion::barnes_hut ? std::max(o.theta, 1e-3) : 0.0;
  Embedding e;
  e.rows = n;
  e.variant = variant_name(rep);
  if (o.progress) o.progress(0.0, "neighbours");
  // The kNN op goes to the device only when it is a GPU (auto): on a CPU OpenCL device the reference's
  // Eigen GEMM is several times faster than the distance kernel and finds the same neighbours.
  const int k = neighbours(t, o.perplexity);
  const Knn g =
      reference ? knn_ref(t, k) : knn(t, k, backend == Backend::cpu ? Backend::cpu : Backend::auto_);
  const double t_knn = ms_since(t0);
  detail::check_cancel(o.cancel);
  if (o.progress) o.progress(0.15, "affinities");
  const Affinities P = tsne_affinities(g, o.perplexity);
  const double t_aff = ms_since(t0) - t_knn;
  std::vector<double> y = detail::tsne_init(t, o.seed);
  const double t_init = ms_since(t0) - t_knn - t_aff;
  detail::FftRepulsion fft;
  std::vector<double> attr, terms;
  const auto ref_grad = [&](const std::vector<double>& yy, double ex, std::vector<double>& out) {
    if (rep != TsneRepulsion::fft) {
      out = tsne_gradient_ref(P, yy, ex, theta);
      return;
    }
    detail::tsne_attraction(P, yy, attr);
    fft.compute(yy, n, o.fft, terms);
    detail::tsne_combine(attr.data(), terms.data(), 3, n, ex, out);
  };
  if (reference) {
    detail::tsne_optimize(y, n, o, ref_grad);
    e.path = "cpu";
  } else {
    const bool worth = ocl::device_is_gpu();
    const char* op = rep == TsneRepulsion::fft ? "projection_tsne_fft" : "projection_tsne";
    const ocl::Path path = ocl::dispatch(
        op, backend, worth,
        [&]() {
          return rep == TsneRepulsion::fft ? ocl::tsne_fft_optimize_ocl(P, o, y)
                                           : ocl::projection_tsne_optimize_ocl(P, o, theta, y);
        },
        [&] {
          y = detail::tsne_init(t, o.seed);  // the device may have moved it before failing
          detail::tsne_optimize(y, n, o, ref_grad);
        });
    e.path = ocl::to_string(path);
  }
  e.xy = std::move(y);
  e.timings_ms = {{"knn", t_knn},
                  {"affinities", t_aff},
                  {"init", t_init},
                  {"optimize", ms_since(t0) - t_knn - t_aff - t_init},
                  {"total", ms_since(t0)}};
  return e;
}
}  // namespace

Embedding tsne_ref(const Table& t, const TsneOptions& o) {
  return run_tsne(t, o, Backend::cpu, true);
}
Embedding tsne(const Table& t, const TsneOptions& o, Backend backend) {
  return run_tsne(t, o, backend, false);
}

}  // namespace trailscope::projection
