// PCA: covariance and scores (the O(N·D²) and O(N·D) products) on the device or in the reference; the
// D×D eigen-solve on the host in both.
#include <Eigen/Dense>

#include <chrono>

#include "ocl/dispatch.hpp"
#include "projection/projection_ocl.hpp"
#include "projection/detail.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/projection/projection.hpp"

namespace trailscope::projection {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

std::vector<double> column_means(const Table& t) {
  std::vector<double> mean(t.cols, 0.0);
  for (std::size_t r = 0; r < t.rows; ++r)
    for (std::size_t c = 0; c < t.cols; ++c) mean[c] += t.values[r * t.cols + c];
  for (double& m : mean) m /= static_cast<double>(t.rows);
  return mean;
}

// The two leading eigenvectors of the covariance (scatter) matrix as a dims × 2 row-major matrix, each
// with its largest-magnitude loading positive. With one column the second is zero.
std::vector<double> components(const std::vector<double>& scatter, std::size_t d) {
  Eigen::MatrixXd c(d, d);
  for (std::size_t a = 0; a < d; ++a)
    for (std::size_t b = 0; b < d; ++b) c(a, b) = 0.5 * (scatter[a * d + b] + scatter[b * d + a]);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(c);
  std::vector<double> w(d * 2, 0.0);
  for (int k = 0; k < 2 && k < static_cast<int>(d); ++k) {
    const Eigen::Index col = static_cast<Eigen::Index>(d) - 1 - k;  // ascending eigenvalues
    Eigen::VectorXd v = es.eigenvectors().col(col);
    Eigen::Index arg = 0;
    v.cwiseAbs().maxCoeff(&arg);
    if (v(arg) < 0) v = -v;
    for (std::size_t a = 0; a < d; ++a) w[a * 2 + k] = v(static_cast<Eigen::Index>(a));
  }
  return w;
}

}  // namespace

Embedding pca_ref(const Table& t) {
  const auto t0 = Clock::now();
  const std::size_t n = t.rows, d = t.cols;
  const std::vector<double> mean = column_means(t);
  std::vector<double> scatter(d * d, 0.0), row(d);
  for (std::size_t r = 0; r < n; ++r) {
    for (std::size_t c = 0; c < d; ++c) row[c] = t.values[r * d + c] - mean[c];
    for (std::size_t a = 0; a < d; ++a)
      for (std::size_t b = a; b < d; ++b) scatter[a * d + b] += row[a] * row[b];
  }
  for (std::size_t a = 0; a < d; ++a)
    for (std::size_t b = 0; b < a; ++b) scatter[a * d + b] = scatter[b * d + a];
  const double t_cov = ms_since(t0);
  const std::vector<double> w = components(scatter, d);
  Embedding e;
  e.rows = n;
  e.xy.assign(2 * n, 0.0);
  for (std::size_t r = 0; r < n; ++r)
    for (std::size_t c = 0; c < d; ++c) {
      const double x = t.values[r * d + c] - mean[c];
      e.xy[2 * r] += x * w[c * 2], e.xy[2 * r + 1] += x * w[c * 2 + 1];
    }
  e.path = "cpu";
  e.variant = "exact";
  e.timings_ms = {{"covariance", t_cov}, {"total", ms_since(t0)}};
  return e;
}

Embedding pca(const Table& t, Backend backend) {
  validate_table(t);
  Embedding e;
  const auto t0 = Clock::now();
  // Worth the device from ~10^7 multiply-adds of covariance; `auto` still needs a GPU (dispatch.hpp).
  const bool worth = ocl::device_is_gpu() && t.rows * t.cols * t.cols > 10'000'000;
  ocl::dispatch(
      "projection_pca", backend, worth,
      [&]() -> std::string {
        const std::size_t n = t.rows, d = t.cols;
        const std::vector<double> mean = column_means(t);
        std::vector<double> scatter(d * d);
        if (auto why = ocl::projection_covariance_ocl(t.values.data(), n, d, mean.data(), scatter.data());
            !why.empty())
          return why;
        const double t_cov = ms_since(t0);
        const std::vector<double> w = components(scatter, d);
        Embedding r;
        r.rows = n;
        r.xy.assign(2 * n, 0.0);
        if (auto why = ocl::projection_scores_ocl(t.values.data(), n, d, mean.data(), w.data(), r.xy.data());
            !why.empty())
          return why;
        r.path = "opencl";
        r.variant = "exact";
        r.timings_ms = {{"covariance", t_cov}, {"total", ms_since(t0)}};
        e = std::move(r);
        return {};
      },
      [&] { e = pca_ref(t); });
  return e;
}

}  // namespace trailscope::projection
