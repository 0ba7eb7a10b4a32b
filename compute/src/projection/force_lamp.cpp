// Force Scheme and LAMP. Force Scheme keeps the N×N distance matrix (float) and moves every point by
// the mean force of all others per iteration; LAMP places ⌈√N⌉ control points with it and maps every
// point by its weighted orthogonal affine map.
#include <Eigen/Dense>
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

constexpr int kLampForceIterations = 100;
// A point closer than this (squared, in the units of the data) to a control point takes its position:
// its weight 1/d² would overflow.
constexpr double kLampCoincident = 1e-12;

void check_force(const Table& t, int iterations) {
  validate_table(t);
  if (t.rows > limits::kMaxForceSchemeRows)
    throw Error(Error::Kind::payload_too_large, "table",
                "Force Scheme takes at most " + std::to_string(limits::kMaxForceSchemeRows) + " rows, not " +
                    std::to_string(t.rows) + " (use lamp, which runs it on √N control points)");
  if (iterations < 1 || iterations > limits::kMaxProjectionIterations)
    throw invalid_argument("iterations", "iterations must be in [1, " +
                                             std::to_string(limits::kMaxProjectionIterations) + "], not " +
                                             std::to_string(iterations));
}

// Distances δ (float, as the device keeps them) in double arithmetic.
std::vector<float> distance_matrix(const Table& t) {
  const std::size_t n = t.rows;
  std::vector<float> delta(n * n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    for (std::size_t j = 0; j < n; ++j) {
      double s = 0;
      for (std::size_t c = 0; c < t.cols; ++c) {
        const double v = static_cast<double>(t.at(i, c)) - t.at(j, c);
        s += v * v;
      }
      delta[i * n + j] = static_cast<float>(std::sqrt(s));
    }
  });
  return delta;
}

double max_of(const std::vector<float>& v) {
  double m = 0;
  for (float x : v) m = std::max(m, static_cast<double>(x));
  return m;
}

void check_controls(const Table& t, const std::vector<std::size_t>& controls,
                    const std::vector<double>& cxy) {
  validate_table(t);
  if (controls.size() < 2) throw invalid_argument("controls", "LAMP needs at least 2 control points");
  if (cxy.size() != 2 * controls.size())
    throw invalid_argument("controls", "control positions must hold controls × 2 values");
  for (std::size_t c : controls)
    if (c >= t.rows) throw invalid_argument("controls", "control index " + std::to_string(c) + " ≥ rows");
}

Table subset(const Table& t, const std::vector<std::size_t>& rows) {
  Table s;
  s.rows = rows.size(), s.cols = t.cols, s.columns = t.columns;
  s.values.resize(s.rows * s.cols);
  for (std::size_t r = 0; r < rows.size(); ++r)
    std::copy_n(t.row(rows[r]), t.cols, s.values.data() + r * t.cols);
  return s;
}

}  // namespace

Embedding force_scheme_ref(const Table& t, int iterations, std::uint64_t seed) {
  check_force(t, iterations);
  const auto t0 = Clock::now();
  const std::size_t n = t.rows;
  const std::vector<float> delta = distance_matrix(t);
  std::vector<double> y = detail::force_init(n, max_of(delta), seed), next(2 * n);
  const double inv_n = 1.0 / static_cast<double>(n);
  for (int it = 0; it < iterations; ++it) {
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t j) {
      double ax = 0, ay = 0;
      for (std::size_t i = 0; i < n; ++i) {
        if (i == j) continue;
        const double vx = y[2 * j] - y[2 * i], vy = y[2 * j + 1] - y[2 * i + 1];
        const double d = std::sqrt(vx * vx + vy * vy);
        if (d < 1e-12) continue;  // coincident: no direction to push along
        const double f = (delta[j * n + i] - d) / d;
        ax += f * vx, ay += f * vy;
      }
      next[2 * j] = y[2 * j] + ax * inv_n, next[2 * j + 1] = y[2 * j + 1] + ay * inv_n;
    });
    y.swap(next);
  }
  Embedding e;
  e.rows = n, e.xy = std::move(y), e.path = "cpu", e.variant = "parallel";
  e.timings_ms = {{"total", ms_since(t0)}};
  return e;
}

Embedding force_scheme(const Table& t, int iterations, std::uint64_t seed, Backend backend) {
  check_force(t, iterations);
  Embedding e;
  ocl::dispatch(
      "projection_force", backend, ocl::device_is_gpu() && t.rows >= 500,
      [&]() -> std::string {
        const auto t0 = Clock::now();
        const std::size_t n = t.rows;
        // The start needs max δ: the device computes δ again, this is the host's O(N²·D) once.
        std::vector<float> delta(n * n);
        if (auto why = ocl::projection_sqdist_ocl(t.values.data(), n, t.values.data(), n, t.cols, true,
                                                  delta.data());
            !why.empty())
          return why;
        std::vector<double> y = detail::force_init(n, max_of(delta), seed);
        if (auto why = ocl::projection_force_ocl(t.values.data(), n, t.cols, iterations, nullptr, y);
            !why.empty())
          return why;
        Embedding r;
        r.rows = n, r.xy = std::move(y), r.path = "opencl", r.variant = "parallel";
        r.timings_ms = {{"total", ms_since(t0)}};
        e = std::move(r);
        return {};
      },
      [&] { e = force_scheme_ref(t, iterations, seed); });
  return e;
}

std::vector<double> lamp_map_ref(const Table& t, const std::vector<std::size_t>& controls,
                                 const std::vector<double>& cxy) {
  check_controls(t, controls, cxy);
  const std::size_t n = t.rows, d = t.cols, k = controls.size();
  std::vector<double> out(2 * n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t a) {
    const float* x = t.row(a);
    std::vector<double> alpha(k);
    double asum = 0;
    for (std::size_t i = 0; i < k; ++i) {
      const float* xi = t.row(controls[i]);
      double s = 0;
      for (std::size_t c = 0; c < d; ++c) {
        const double v = static_cast<double>(xi[c]) - x[c];
        s += v * v;
      }
      if (s < kLampCoincident) {
        out[2 * a] = cxy[2 * i], out[2 * a + 1] = cxy[2 * i + 1];
        return;
      }
      alpha[i] = 1.0 / s, asum += alpha[i];
    }
    Eigen::VectorXd xt = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(d));
    Eigen::Vector2d yt = Eigen::Vector2d::Zero();
    for (std::size_t i = 0; i < k; ++i) {
      for (std::size_t c = 0; c < d; ++c) xt(static_cast<Eigen::Index>(c)) += alpha[i] * t.at(controls[i], c);
      yt += alpha[i] * Eigen::Vector2d(cxy[2 * i], cxy[2 * i + 1]);
    }
    xt /= asum, yt /= asum;
    Eigen::MatrixXd A(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(d));
    Eigen::MatrixXd B(static_cast<Eigen::Index>(k), 2);
    for (std::size_t i = 0; i < k; ++i) {
      const double s = std::sqrt(alpha[i]);
      for (std::size_t c = 0; c < d; ++c)
        A(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(c)) =
            s * (t.at(controls[i], c) - xt(static_cast<Eigen::Index>(c)));
      B(static_cast<Eigen::Index>(i), 0) = s * (cxy[2 * i] - yt(0));
      B(static_cast<Eigen::Index>(i), 1) = s * (cxy[2 * i + 1] - yt(1));
    }
    const Eigen::MatrixXd m = A.transpose() * B;  // d × 2
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(m, Eigen::ComputeThinU | Eigen::ComputeThinV);
    // M = U·Vᵀ over the singular directions that exist (a zero singular value has no direction to keep;
    // the kernel's pseudo-inverse square root drops the same ones: float rounding leaves ~1e-7 relative
    // noise in a zero eigenvalue of CᵀC, so both drop singular values below 1e-3 of the largest).
    const auto& sv = svd.singularValues();
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(d), 2);
    for (Eigen::Index s = 0; s < sv.size(); ++s)
      if (sv(s) > 1e-3 * sv(0)) M += svd.matrixU().col(s) * svd.matrixV().col(s).transpose();
    Eigen::VectorXd xa(static_cast<Eigen::Index>(d));
    for (std::size_t c = 0; c < d; ++c)
      xa(static_cast<Eigen::Index>(c)) = x[c] - xt(static_cast<Eigen::Index>(c));
    const Eigen::Vector2d ya = M.transpose() * xa + yt;
    out[2 * a] = ya(0), out[2 * a + 1] = ya(1);
  });
  return out;
}

namespace {
std::vector<double> lamp_map_on(const Table& t, const std::vector<std::size_t>& controls,
                                const std::vector<double>& cxy, Backend backend, ocl::Path& path) {
  check_controls(t, controls, cxy);
  std::vector<double> out;
  path = ocl::dispatch(
      "projection_lamp", backend, ocl::device_is_gpu() && t.rows >= 2000,
      [&]() { return ocl::projection_lamp_map_ocl(t.values.data(), t.rows, t.cols, controls, cxy, out); },
      [&] { out = lamp_map_ref(t, controls, cxy); });
  return out;
}
}  // namespace

std::vector<double> lamp_map(const Table& t, const std::vector<std::size_t>& controls,
                             const std::vector<double>& cxy, Backend backend) {
  ocl::Path path;
  return lamp_map_on(t, controls, cxy, backend, path);
}

namespace {
Embedding run_lamp(const Table& t, std::uint64_t seed, Backend backend, bool reference) {
  validate_table(t);
  const auto t0 = Clock::now();
  const std::vector<std::size_t> controls =
      detail::sample_indices(t.rows, detail::lamp_controls(t.rows), seed);
  const Table ct = subset(t, controls);
  const Embedding placed = reference ? force_scheme_ref(ct, kLampForceIterations, seed)
                                     : force_scheme(ct, kLampForceIterations, seed, backend);
  const double t_force = ms_since(t0);
  Embedding e;
  e.rows = t.rows;
  if (reference) {
    e.xy = lamp_map_ref(t, controls, placed.xy);
    e.path = "cpu";
  } else {
    ocl::Path path;
    e.xy = lamp_map_on(t, controls, placed.xy, backend, path);
    e.path = ocl::to_string(path);
  }
  e.variant = "controls=" + std::to_string(controls.size());
  e.timings_ms = {{"controls", t_force}, {"map", ms_since(t0) - t_force}, {"total", ms_since(t0)}};
  return e;
}
}  // namespace

Embedding lamp_ref(const Table& t, std::uint64_t seed) {
  return run_lamp(t, seed, Backend::cpu, true);
}
Embedding lamp(const Table& t, std::uint64_t seed, Backend backend) {
  return run_lamp(t, seed, backend, false);
}

}  // namespace trailscope::projection
