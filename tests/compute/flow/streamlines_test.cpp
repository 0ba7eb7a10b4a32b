// Evenly spaced streamlines (trailscope/flow/streamlines.hpp) on analytic fields against their closed-form
// paths, and the spacing guarantee checked by brute force over every pair of points.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "trailscope/core/error.hpp"
#include "trailscope/flow/streamlines.hpp"

namespace trailscope::flow {
namespace {

/// A field sampled at the cell centres from an analytic velocity (x east, y south, cell coordinates),
/// constant traffic 10, so that only the direction matters.
SectorField analytic(int nx, int ny, const std::function<std::pair<double, double>(double, double)>& v) {
  SectorField f;
  f.sx.resize(static_cast<std::size_t>(nx) * ny), f.sy.resize(f.sx.size()), f.w.assign(f.sx.size(), 10.f);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const auto [u, w] = v(i + 0.5, j + 0.5);
      f.sx[static_cast<std::size_t>(j) * nx + i] = static_cast<float>(u);
      f.sy[static_cast<std::size_t>(j) * nx + i] = static_cast<float>(w);
    }
  return f;
}

StreamlineParams params() {
  StreamlineParams p;
  p.d_sep = 2;
  p.step = 0.25;
  p.min_traffic = 1;
  p.min_coherence = 0;
  p.min_length = 2;
  return p;
}

/// No point of one line is closer than d_test to a point of another (all pairs).
void expect_separated(const Streamlines& s, double d_test) {
  const auto& L = s.lines;
  double worst = 1e300;
  for (std::size_t a = 0; a < L.size(); ++a)
    for (std::size_t b = a + 1; b < L.size(); ++b)
      for (std::size_t i = L.begin(a); i < L.end(a); ++i)
        for (std::size_t k = L.begin(b); k < L.end(b); ++k)
          worst = std::min(worst, std::hypot(L.x[i] - L.x[k], L.y[i] - L.y[k]));
  EXPECT_GE(worst, d_test - 1e-9) << "closest points of two lines";
}

TEST(Streamlines, UniformFieldGivesStraightLinesDSepApart) {
  const int n = 40;
  const auto p = params();
  const Streamlines s = evenly_spaced_streamlines(analytic(n, n,
                                                           [](double, double) {
                                                             return std::pair{1.0, 0.0};
                                                           }),
                                                  n, n, p);
  ASSERT_GT(s.lines.size(), 0u);
  std::vector<double> rows;
  for (std::size_t l = 0; l < s.lines.size(); ++l) {
    const std::size_t b = s.lines.begin(l);
    for (std::size_t k = b; k < s.lines.end(l); ++k)
      EXPECT_DOUBLE_EQ(s.lines.y[k], s.lines.y[b]);  // y = const
    for (std::size_t k = b + 1; k < s.lines.end(l); ++k)
      EXPECT_GT(s.lines.x[k], s.lines.x[k - 1]);  // flows east
    // A full line spans the domain (it stops within one step of each edge, or at max_line_points).
    EXPECT_LE(s.lines.x[b], 0.5 + p.step + 1e-9);
    EXPECT_GE(s.lines.x[s.lines.end(l) - 1], n - 0.5 - p.step - 1e-9);
    rows.push_back(s.lines.y[b]);
  }
  std::sort(rows.begin(), rows.end());
  for (std::size_t k = 1; k < rows.size(); ++k) EXPECT_NEAR(rows[k] - rows[k - 1], p.d_sep, 1e-9);
  // The rows fill the domain: no gap at either edge wider than d_sep.
  EXPECT_LT(rows.front() - 0.5, p.d_sep);
  EXPECT_LT(n - 0.5 - rows.back(), p.d_sep);
  expect_separated(s, p.d_test * p.d_sep);
}

TEST(Streamlines, RotationGivesCirclesAboutTheCentre) {
  const int n = 48;
  const double c = n / 2.0;
  for (const Integrator integ : {Integrator::rk2, Integrator::rk4}) {
    auto p = params();
    p.integrator = integ;
    const Streamlines s = evenly_spaced_streamlines(analytic(n, n,
                                                             [c](double x, double y) {
                                                               return std::pair{-(y - c), x - c};
                                                             }),
                                                    n, n, p);
    ASSERT_GT(s.lines.size(), 3u);
    // The field is stored in float: its direction is exact to ~1e-7; the rest is the step's truncation.
    const double tol = integ == Integrator::rk4 ? 1e-4 : 2e-3;
    for (std::size_t l = 0; l < s.lines.size(); ++l) {
      const std::size_t b = s.lines.begin(l);
      const double r0 = std::hypot(s.lines.x[b] - c, s.lines.y[b] - c);
      for (std::size_t k = b; k < s.lines.end(l); ++k)
        ASSERT_NEAR(std::hypot(s.lines.x[k] - c, s.lines.y[k] - c), r0, tol * std::max(1.0, r0))
            << to_string(integ) << " line " << l << " point " << k - b;
      // Clockwise on screen (y down): the angle grows.
      if (s.lines.end(l) - b > 2) {
        const double a0 = std::atan2(s.lines.y[b] - c, s.lines.x[b] - c);
        const double a1 = std::atan2(s.lines.y[b + 1] - c, s.lines.x[b + 1] - c);
        EXPECT_GT(std::remainder(a1 - a0, 2 * M_PI), 0);
      }
    }
    expect_separated(s, p.d_test * p.d_sep);
  }
}

TEST(Streamlines, SaddleFollowsHyperbolas) {
  const int n = 48;
  const double c = n / 2.0 + 0.25;  // off the cell centres: no line starts on an axis
  const auto p = params();
  const Streamlines s = evenly_spaced_streamlines(analytic(n, n,
                                                           [c](double x, double y) {
                                                             return std::pair{x - c, -(y - c)};
                                                           }),
                                                  n, n, p);
  ASSERT_GT(s.lines.size(), 4u);
  for (std::size_t l = 0; l < s.lines.size(); ++l) {
    const std::size_t b = s.lines.begin(l);
    const double i0 = (s.lines.x[b] - c) * (s.lines.y[b] - c);  // (x − c)(y − c) is constant on a path
    for (std::size_t k = b; k < s.lines.end(l); ++k)
      ASSERT_NEAR((s.lines.x[k] - c) * (s.lines.y[k] - c), i0, 1e-4 * std::max(1.0, std::abs(i0)))
          << "line " << l << " point " << k - b;
  }
  expect_separated(s, p.d_test * p.d_sep);
}

TEST(Streamlines, SeparationHoldsOnAnIrregularField) {
  const int n = 40;
  auto p = params();
  p.d_sep = 1.5, p.d_test = 0.6;
  const Streamlines s =
      evenly_spaced_streamlines(analytic(n, n,
                                         [](double x, double y) {
                                           return std::pair{std::sin(0.3 * y) + 0.2, std::cos(0.25 * x)};
                                         }),
                                n, n, p);
  ASSERT_GT(s.lines.size(), 10u);
  expect_separated(s, p.d_test * p.d_sep);
  ASSERT_EQ(s.traffic.size(), s.lines.points());
}

TEST(Streamlines, NoFlowWhereTrafficIsBelowTheThreshold) {
  const int n = 20;
  SectorField f = analytic(n, n, [](double, double) { return std::pair{0.0, 1.0}; });
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n / 2; ++i)
      f.w[static_cast<std::size_t>(j) * n + i] = 0.5f;  // the west half: too little
  const auto p = params();
  const Streamlines s = evenly_spaced_streamlines(f, n, n, p);
  ASSERT_GT(s.lines.size(), 0u);
  for (std::size_t k = 0; k < s.lines.points(); ++k) EXPECT_GE(s.traffic[k], p.min_traffic);
}

TEST(Streamlines, TooManyPointsAndBadParametersAreRefused) {
  const int n = 40;
  const SectorField f = analytic(n, n, [](double, double) { return std::pair{1.0, 0.0}; });
  try {
    evenly_spaced_streamlines(f, n, n, params(), 100);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::payload_too_large);
    EXPECT_EQ(e.param(), "d_sep");
  }
  StreamlineParams p;
  EXPECT_THROW(p.set("d_sep", "0.1"), Error);
  EXPECT_THROW(p.set("integrator", "euler"), Error);
  EXPECT_THROW(p.set("nope", "1"), Error);
  EXPECT_EQ(p.d_sep, 3);  // unchanged by the failures
  p.set("step", "0.75");
  EXPECT_EQ(p.step, 0.75);
}

}  // namespace
}  // namespace trailscope::flow
