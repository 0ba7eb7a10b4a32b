// Quality metrics against a direct O(N³) computation written from the definitions (quality.hpp),
// against values worked out by hand, and on layouts whose quality is known exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "projection_test_util.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/projection/quality.hpp"

namespace trailscope::projection {
namespace {

// --- the naive computation: every rank by counting, no sorting, no shared code -----------------------
struct Naive {
  double t, c, np, stress, shepard;
};

double naive_d(const std::vector<double>& p, std::size_t dims, std::size_t i, std::size_t j) {
  double s = 0;
  for (std::size_t c = 0; c < dims; ++c)
    s += (p[i * dims + c] - p[j * dims + c]) * (p[i * dims + c] - p[j * dims + c]);
  return std::sqrt(s);
}

// rank of j from i: 1 + the rows l ∉ {i, j} strictly before j in (distance, index) order.
std::size_t naive_rank(const std::vector<double>& p, std::size_t dims, std::size_t n, std::size_t i,
                       std::size_t j) {
  std::size_t r = 1;
  const double dj = naive_d(p, dims, i, j);
  for (std::size_t l = 0; l < n; ++l) {
    if (l == i || l == j) continue;
    const double dl = naive_d(p, dims, i, l);
    if (dl < dj || (dl == dj && l < j)) ++r;
  }
  return r;
}

std::vector<double> ranks_with_ties(const std::vector<double>& v) {
  std::vector<double> r(v.size());
  for (std::size_t a = 0; a < v.size(); ++a) {
    double less = 0, equal = 0;
    for (std::size_t b = 0; b < v.size(); ++b) less += v[b] < v[a], equal += v[b] == v[a];
    r[a] = less + (equal + 1) / 2;  // average of the tied positions less+1 .. less+equal
  }
  return r;
}

Naive naive(const Table& t, const std::vector<double>& xy, int k) {
  const std::size_t n = t.rows;
  std::vector<double> x(t.values.begin(), t.values.end());
  double tsum = 0, csum = 0, np = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      const std::size_t r = naive_rank(x, t.cols, n, i, j), rh = naive_rank(xy, 2, n, i, j);
      if (rh <= static_cast<std::size_t>(k)) tsum += std::max<double>(0, static_cast<double>(r) - k);
      if (r <= static_cast<std::size_t>(k)) csum += std::max<double>(0, static_cast<double>(rh) - k);
      if (r <= static_cast<std::size_t>(k) && rh <= static_cast<std::size_t>(k)) np += 1;
    }
  const double nn = n, kk = k;
  const double norm = 2.0 / (nn * kk * (2 * nn - 3 * kk - 1));
  std::vector<double> d, dh;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      d.push_back(naive_d(x, t.cols, i, j)), dh.push_back(naive_d(xy, 2, i, j));
  // Stress minimised over α by a direct scan refinement (not the closed form the library uses).
  const auto stress_at = [&](double a) {
    double num = 0, den = 0;
    for (std::size_t e = 0; e < d.size(); ++e)
      num += (d[e] - a * dh[e]) * (d[e] - a * dh[e]), den += d[e] * d[e];
    return num / den;
  };
  double lo = 0, hi = 1e3;
  for (int it = 0; it < 300; ++it) {  // golden-section search: stress(α) is a convex parabola
    const double m1 = lo + (hi - lo) * 0.381966, m2 = lo + (hi - lo) * 0.618034;
    (stress_at(m1) < stress_at(m2) ? hi : lo) = (stress_at(m1) < stress_at(m2) ? m2 : m1);
  }
  const std::vector<double> ra = ranks_with_ties(d), rb = ranks_with_ties(dh);
  const double mean = (static_cast<double>(d.size()) + 1) / 2;
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t e = 0; e < d.size(); ++e)
    sab += (ra[e] - mean) * (rb[e] - mean), saa += (ra[e] - mean) * (ra[e] - mean),
        sbb += (rb[e] - mean) * (rb[e] - mean);
  return {1 - norm * tsum, 1 - norm * csum, np / (nn * kk), stress_at(0.5 * (lo + hi)),
          sab / std::sqrt(saa * sbb)};
}

Table table_of(const std::vector<double>& v, std::size_t cols) {
  Table t;
  t.cols = cols, t.rows = v.size() / cols;
  t.values.assign(v.begin(), v.end());
  return t;
}

QualityOptions cpu(int k) {
  QualityOptions o;
  o.k = k;
  o.backend = Backend::cpu;
  return o;
}

TEST(ProjectionQuality, IdentityOf2dDataIsPerfect) {
  const Table t = test::gaussian_clusters(200, 2, 3, 10.0, 7);
  const std::vector<double> xy(t.values.begin(), t.values.end());
  const Quality q = quality_ref(t, xy, cpu(10));
  EXPECT_DOUBLE_EQ(q.trustworthiness, 1.0);
  EXPECT_DOUBLE_EQ(q.continuity, 1.0);
  EXPECT_DOUBLE_EQ(q.neighborhood_preservation, 1.0);
  EXPECT_NEAR(q.stress, 0.0, 1e-15);
  EXPECT_NEAR(q.shepard, 1.0, 1e-12);
  EXPECT_FALSE(q.sampled);
  EXPECT_EQ(q.queries, 200u);
}

TEST(ProjectionQuality, SimilarityTransformIsPerfectAndStressIsScaleFree) {
  // scikit-learn's own check: trustworthiness(X, 5 + X / 10) == 1. Rotating as well changes nothing;
  // the scale-normalised stress stays 0 although the raw stress of X/10 would be 0.81.
  const Table t = test::gaussian_clusters(150, 2, 4, 8.0, 3);
  std::vector<double> xy(2 * t.rows);
  const double c = std::cos(0.7), s = std::sin(0.7);
  for (std::size_t i = 0; i < t.rows; ++i) {
    const double x = t.at(i, 0), y = t.at(i, 1);
    xy[2 * i] = 5 + (c * x - s * y) / 10, xy[2 * i + 1] = 5 + (s * x + c * y) / 10;
  }
  const Quality q = quality_ref(t, xy, cpu(7));
  EXPECT_DOUBLE_EQ(q.trustworthiness, 1.0);
  EXPECT_DOUBLE_EQ(q.continuity, 1.0);
  EXPECT_NEAR(q.stress, 0.0, 1e-12);
  EXPECT_NEAR(q.shepard, 1.0, 1e-12);
}

TEST(ProjectionQuality, HandWorkedExample) {
  // Data 0,1,2,3,4 on a line, laid out at 0,2,4,1,3 (scikit-learn's "completely different" case), k = 1.
  // Layout neighbour (ties by lower index) and its data rank r, penalty r − 1:
  //   0 → 3 (r 3, 2); 1 → 3 (r 3, 2); 2 → 4 (r 4, 3: 1 and 3 at 1, then 0 before 4 at 2);
  //   3 → 0 (r 4, 3); 4 → 1 (r 3, 2): sum 12, T = 1 − 12·2/(5·1·(10 − 3 − 1)) = 0.2, the value
  //   scikit-learn's test_trustworthiness asserts for this case.
  // Data neighbour and its layout rank r̂, penalty r̂ − 1: 0 → 1 (r̂ 2, 1), 1 → 0 (r̂ 3, 2),
  //   2 → 1 (r̂ 2, 1), 3 → 2 (r̂ 4, 3), 4 → 3 (r̂ 3, 2): sum 9, C = 1 − 18/30. No neighbour is kept: NP 0.
  const Table t = table_of({0, 1, 2, 3, 4}, 1);
  const std::vector<double> xy = {0, 0, 2, 0, 4, 0, 1, 0, 3, 0};
  const Quality q = quality_ref(t, xy, cpu(1));
  EXPECT_NEAR(q.trustworthiness, 0.2, 1e-15);
  EXPECT_NEAR(q.continuity, 1.0 - 18.0 / 30.0, 1e-15);
  EXPECT_NEAR(q.neighborhood_preservation, 0.0, 1e-15);
  const Naive nv = naive(t, xy, 1);
  EXPECT_NEAR(nv.t, q.trustworthiness, 1e-15);
  EXPECT_NEAR(nv.c, q.continuity, 1e-15);
}

TEST(ProjectionQuality, MatchesTheNaiveComputation) {
  // 3D data with ties (integer grid coordinates) laid out by a noisy, partly wrong projection.
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> g(0, 4);
  std::normal_distribution<double> noise(0, 0.7);
  std::vector<double> v;
  for (int i = 0; i < 70 * 3; ++i) v.push_back(g(rng));
  const Table t = table_of(v, 3);
  std::vector<double> xy(2 * t.rows);
  for (std::size_t i = 0; i < t.rows; ++i)
    xy[2 * i] = t.at(i, 0) + noise(rng), xy[2 * i + 1] = t.at(i, 1) + t.at(i, 2) * 0.3 + noise(rng);
  for (int k : {1, 5, 12}) {
    const Quality q = quality_ref(t, xy, cpu(k));
    const Naive nv = naive(t, xy, k);
    EXPECT_NEAR(q.trustworthiness, nv.t, 1e-12) << "k=" << k;
    EXPECT_NEAR(q.continuity, nv.c, 1e-12) << "k=" << k;
    EXPECT_NEAR(q.neighborhood_preservation, nv.np, 1e-12) << "k=" << k;
    EXPECT_NEAR(q.stress, nv.stress, 1e-9) << "k=" << k;
    EXPECT_NEAR(q.shepard, nv.shepard, 1e-12) << "k=" << k;
    EXPECT_LT(q.trustworthiness, 1.0);
    EXPECT_GT(q.trustworthiness, 0.5);
  }
}

TEST(ProjectionQuality, RandomLayoutScoresLow) {
  const Table t = test::gaussian_clusters(300, 5, 3, 20.0, 5);
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> xy(2 * t.rows);
  for (double& c : xy) c = u(rng);
  const Quality q = quality_ref(t, xy, cpu(10));
  // A random layout keeps about k/N of the neighbours and its trustworthiness is near 0.5.
  EXPECT_LT(q.neighborhood_preservation, 0.1);
  EXPECT_NEAR(q.trustworthiness, 0.5, 0.1);
  EXPECT_LT(std::abs(q.shepard), 0.2);
}

TEST(ProjectionQuality, SampledEstimateIsCloseToExact) {
  const Table t = test::gaussian_clusters(2500, 6, 5, 6.0, 9);
  std::vector<double> xy(2 * t.rows);
  for (std::size_t i = 0; i < t.rows; ++i)
    xy[2 * i] = t.at(i, 0), xy[2 * i + 1] = t.at(i, 1) + 0.5 * t.at(i, 2);
  QualityOptions o = cpu(10);
  o.sample = 2500;
  const Quality exact = quality_ref(t, xy, o);
  o.sample = 400;
  const Quality s = quality_ref(t, xy, o);
  EXPECT_TRUE(s.sampled);
  EXPECT_EQ(s.queries, 400u);
  // 400 of 2500 queries: the per-query sums have a std of a few 1e-2, so the mean is within ~0.005.
  EXPECT_NEAR(s.trustworthiness, exact.trustworthiness, 0.01);
  EXPECT_NEAR(s.continuity, exact.continuity, 0.01);
  EXPECT_NEAR(s.neighborhood_preservation, exact.neighborhood_preservation, 0.02);
  // Shepard and stress use only the pairs among the 400 queries (80k pairs of 400 points, not
  // independent): their sampling error is a few 1e-2.
  EXPECT_NEAR(s.shepard, exact.shepard, 0.06);
}

TEST(ProjectionQuality, BadInputsNameTheParameter) {
  const Table t = test::gaussian_clusters(20, 3, 2, 5.0, 1);
  std::vector<double> xy(2 * t.rows, 0.0);
  const auto param_of = [&](const std::vector<double>& layout, int k) -> std::string {
    try {
      (void)quality_ref(t, layout, cpu(k));
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), Error::Kind::invalid_argument);
      return e.param();
    }
    return "no error";
  };
  EXPECT_EQ(param_of(xy, 0), "k");
  EXPECT_EQ(param_of(xy, 10), "k");  // k must stay below N/2
  EXPECT_EQ(param_of(std::vector<double>(7, 0.0), 3), "xy");
  std::vector<double> bad = xy;
  bad[3] = std::nan("");
  EXPECT_EQ(param_of(bad, 3), "xy");
}

}  // namespace
}  // namespace trailscope::projection
