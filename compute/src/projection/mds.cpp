// Classical MDS (exact up to limits::kMaxExactMdsRows, landmark MDS above). The distance matrices and
// the B·V products are the device's part; the small eigen-solves are shared host code (detail.hpp).
#include <tbb/parallel_for.h>

#include <chrono>

#include "ocl/dispatch.hpp"
#include "projection/projection_ocl.hpp"
#include "projection/detail.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/projection/projection.hpp"

namespace trailscope::projection {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

double sqdist(const Table& t, std::size_t a, const float* b) {
  const float* x = t.row(a);
  double s = 0;
  for (std::size_t c = 0; c < t.cols; ++c) {
    const double v = static_cast<double>(x[c]) - b[c];
    s += v * v;
  }
  return s;
}

// Coordinates from the top eigenpairs: v·√λ (λ < 0 from rounding gives 0).
std::vector<double> scale_by_root(const detail::TopEigen& te, std::size_t n) {
  std::vector<double> xy(2 * n);
  for (int c = 0; c < 2; ++c) {
    const double s = std::sqrt(std::max(te.lambda[c], 0.0));
    for (std::size_t i = 0; i < n; ++i) xy[2 * i + c] = te.v[2 * i + c] * s;
  }
  return xy;
}

// Landmark MDS given a function that fills the squared distances of rows [r0, r1) of t to the
// landmarks (row-major, (r1 − r0) × L); shared by both paths.
template <class Fill>
std::vector<double> landmark_layout(const Table& t, const std::vector<std::size_t>& lm, Fill&& fill) {
  const std::size_t n = t.rows, L = lm.size();
  std::vector<double> dl(L * L);
  std::vector<double> xy(2 * n, 0.0);
  std::vector<double> chunk;
  detail::LandmarkMap map;
  {  // the L×L block first (the map needs it): the landmark rows against themselves
    Table lt;
    lt.rows = L, lt.cols = t.cols;
    lt.values.resize(L * t.cols);
    for (std::size_t j = 0; j < L; ++j) std::copy_n(t.row(lm[j]), t.cols, lt.values.data() + j * t.cols);
    fill(lt, 0, L, chunk);
    for (std::size_t i = 0; i < L; ++i)
      for (std::size_t j = 0; j < L; ++j) dl[i * L + j] = 0.5 * (chunk[i * L + j] + chunk[j * L + i]);
    for (std::size_t i = 0; i < L; ++i) dl[i * L + i] = 0;
    map = detail::landmark_map(dl, L);
  }
  const std::size_t step = std::max<std::size_t>(1, (std::size_t{16} << 20) / std::max<std::size_t>(L, 1));
  for (std::size_t r0 = 0; r0 < n; r0 += step) {
    const std::size_t r1 = std::min(n, r0 + step);
    fill(t, r0, r1, chunk);
    tbb::parallel_for(r0, r1, [&](std::size_t r) {
      double x = 0, y = 0;
      const double* d = chunk.data() + (r - r0) * L;
      for (std::size_t j = 0; j < L; ++j) {
        const double delta = d[j] - map.mean[j];
        x += delta * map.pinv[2 * j], y += delta * map.pinv[2 * j + 1];
      }
      xy[2 * r] = -0.5 * x, xy[2 * r + 1] = -0.5 * y;
    });
  }
  return xy;
}

std::vector<std::size_t> landmarks(std::size_t n, std::uint64_t seed) {
  return detail::sample_indices(n, std::min(n, limits::kMdsLandmarks), seed);
}

}  // namespace

Embedding mds_ref(const Table& t, std::uint64_t seed) {
  const auto t0 = Clock::now();
  const std::size_t n = t.rows;
  Embedding e;
  e.rows = n;
  e.path = "cpu";
  if (n <= limits::kMaxExactMdsRows) {
    // B = −½·J·D²·J in double.
    std::vector<double> b(n * n);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
      for (std::size_t j = 0; j < n; ++j) b[i * n + j] = sqdist(t, i, t.row(j));
    });
    std::vector<double> rowm(n, 0.0);
    double grand = 0;
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j = 0; j < n; ++j) rowm[i] += b[i * n + j];
      grand += rowm[i];
      rowm[i] /= static_cast<double>(n);
    }
    grand /= static_cast<double>(n) * static_cast<double>(n);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
      for (std::size_t j = 0; j < n; ++j) b[i * n + j] = -0.5 * (b[i * n + j] - rowm[i] - rowm[j] + grand);
    });
    const double t_b = ms_since(t0);
    const detail::TopEigen te = detail::top_eigen(
        n,
        [&](const std::vector<double>& v, int p, std::vector<double>& out) {
          out.assign(n * p, 0.0);
          tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
            for (std::size_t j = 0; j < n; ++j) {
              const double bij = b[i * n + j];
              for (int c = 0; c < p; ++c) out[i * p + c] += bij * v[j * p + c];
            }
          });
        },
        seed, detail::kEigenTol, detail::kEigenMaxIter, nullptr);
    e.xy = scale_by_root(te, n);
    e.variant = "exact";
    e.timings_ms = {{"distances", t_b}, {"eigen", ms_since(t0) - t_b}};
  } else {
    const std::vector<std::size_t> lm = landmarks(n, seed);
    std::vector<float> lrows(lm.size() * t.cols);
    for (std::size_t j = 0; j < lm.size(); ++j) std::copy_n(t.row(lm[j]), t.cols, lrows.data() + j * t.cols);
    e.xy = landmark_layout(t, lm,
                           [&](const Table& src, std::size_t r0, std::size_t r1, std::vector<double>& out) {
                             const std::size_t L = lm.size();
                             out.assign((r1 - r0) * L, 0.0);
                             tbb::parallel_for(r0, r1, [&](std::size_t r) {
                               for (std::size_t j = 0; j < L; ++j)
                                 out[(r - r0) * L + j] = sqdist(src, r, lrows.data() + j * t.cols);
                             });
                           });
    e.variant = "landmark";
  }
  detail::normalize_signs(e.xy, n);
  e.timings_ms.emplace_back("total", ms_since(t0));
  return e;
}

Embedding mds(const Table& t, std::uint64_t seed, Backend backend) {
  validate_table(t);
  Embedding e;
  const bool worth = ocl::device_is_gpu() && t.rows >= 1000;
  ocl::dispatch(
      "projection_mds", backend, worth,
      [&]() -> std::string {
        const auto t0 = Clock::now();
        const std::size_t n = t.rows;
        Embedding r;
        r.rows = n;
        r.path = "opencl";
        if (n <= limits::kMaxExactMdsRows) {
          if (auto why = ocl::projection_mds_exact_ocl(t.values.data(), n, t.cols, seed, nullptr, r.xy);
              !why.empty())
            return why;
          r.variant = "exact";
        } else {
          const std::vector<std::size_t> lm = landmarks(n, seed);
          std::vector<float> lrows(lm.size() * t.cols), buf;
          for (std::size_t j = 0; j < lm.size(); ++j)
            std::copy_n(t.row(lm[j]), t.cols, lrows.data() + j * t.cols);
          std::string why;
          r.xy = landmark_layout(
              t, lm, [&](const Table& src, std::size_t r0, std::size_t r1, std::vector<double>& out) {
                const std::size_t L = lm.size();
                buf.resize((r1 - r0) * L);
                if (why.empty())
                  why = ocl::projection_sqdist_ocl(src.row(r0), r1 - r0, lrows.data(), L, t.cols, false,
                                                   buf.data());
                out.assign(buf.begin(), buf.end());
              });
          if (!why.empty()) return why;
          r.variant = "landmark";
        }
        detail::normalize_signs(r.xy, n);
        r.timings_ms = {{"total", ms_since(t0)}};
        e = std::move(r);
        return {};
      },
      [&] { e = mds_ref(t, seed); });
  return e;
}

}  // namespace trailscope::projection
