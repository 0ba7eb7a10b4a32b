// The projection methods' references against independent computations and known geometry: PCA against
// Eigen's SVD of the centred data, MDS recovering exactly-2D point sets, t-SNE separating clusters,
// Force Scheme and LAMP on isometric data, and exact errors for bad options.
#include <gtest/gtest.h>

// The test areas do not link Eigen3::Eigen (tests/CMakeLists.txt); Debian installs it under eigen3/.
#include <eigen3/Eigen/Dense>

#include <cmath>
#include <random>

#include "projection_test_util.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/projection/projection.hpp"
#include "trailscope/projection/quality.hpp"

namespace trailscope::projection {
namespace {

// n points of a 2D set (a noisy ring plus a blob, so no eigenvalue ties) placed isometrically in `dims`
// dimensions by a random orthonormal 2-frame plus an offset. true2d receives the 2D coordinates.
Table planar(std::size_t n, std::size_t dims, std::uint64_t seed, std::vector<double>& true2d) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0, 1);
  Eigen::MatrixXd frame(dims, 2);
  for (auto& v : frame.reshaped()) v = g(rng);
  frame = Eigen::HouseholderQR<Eigen::MatrixXd>(frame).householderQ() * Eigen::MatrixXd::Identity(dims, 2);
  Table t;
  t.rows = n, t.cols = dims;
  true2d.resize(2 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 0.1 * static_cast<double>(i);
    const double x = i % 3 ? 4 * std::cos(a) : 0.7 * g(rng) + 1, y = i % 3 ? 2 * std::sin(a) : 0.5 * g(rng);
    true2d[2 * i] = x, true2d[2 * i + 1] = y;
    for (std::size_t d = 0; d < dims; ++d)
      t.values.push_back(static_cast<float>(frame(d, 0) * x + frame(d, 1) * y + 3.0));
  }
  // The float rounding of the table is the data; recompute the 2D truth from it for exact comparisons.
  return t;
}

double max_distance_error(const Table& t, const std::vector<double>& xy, std::size_t pairs_from = 0) {
  double worst = 0, scale = 0;
  for (std::size_t i = pairs_from; i < t.rows; i += 7)
    for (std::size_t j = 0; j < t.rows; j += 5) {
      double s = 0;
      for (std::size_t c = 0; c < t.cols; ++c)
        s += (double(t.at(i, c)) - t.at(j, c)) * (double(t.at(i, c)) - t.at(j, c));
      worst = std::max(worst, std::abs(std::sqrt(s) - test::dist2d(xy, i, j)));
      scale = std::max(scale, std::sqrt(s));
    }
  return worst / scale;
}

TEST(ProjectionPca, MatchesSvdOfTheCentredData) {
  const Table t = test::gaussian_clusters(400, 12, 4, 6.0, 21);
  const Embedding e = pca_ref(t);
  Eigen::MatrixXd x(t.rows, t.cols);
  for (std::size_t r = 0; r < t.rows; ++r)
    for (std::size_t c = 0; c < t.cols; ++c) x(r, c) = t.at(r, c);
  x.rowwise() -= x.colwise().mean();
  Eigen::BDCSVD<Eigen::MatrixXd> svd(x, Eigen::ComputeThinU | Eigen::ComputeThinV);
  for (int k = 0; k < 2; ++k) {
    Eigen::VectorXd v = svd.matrixV().col(k);
    Eigen::Index arg;
    v.cwiseAbs().maxCoeff(&arg);
    const double sign = v(arg) < 0 ? -1 : 1;  // the documented sign rule, applied to the SVD's V
    for (std::size_t r = 0; r < t.rows; ++r)
      EXPECT_NEAR(e.xy[2 * r + k], sign * svd.matrixU()(r, k) * svd.singularValues()(k), 1e-9)
          << r << "," << k;
  }
  EXPECT_EQ(e.path, "cpu");
}

TEST(ProjectionPca, OneColumnAndConstantData) {
  Table t;
  t.rows = 4, t.cols = 1, t.values = {1, 2, 3, 6};
  const Embedding e = pca_ref(t);
  EXPECT_NEAR(std::abs(e.xy[0]), 2.0, 1e-12);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(e.xy[2 * i + 1], 0.0);
  t.values = {5, 5, 5, 5};
  for (double v : pca_ref(t).xy) EXPECT_EQ(v, 0.0);
}

TEST(ProjectionMds, ExactRecoversPlanarDistances) {
  std::vector<double> truth;
  const Table t = planar(300, 7, 4, truth);
  const Embedding e = mds_ref(t, 1);
  EXPECT_EQ(e.variant, "exact");
  EXPECT_LT(max_distance_error(t, e.xy), 1e-5);
  QualityOptions qo;
  qo.backend = Backend::cpu;
  EXPECT_LT(quality_ref(t, e.xy, qo).stress, 1e-9);
}

TEST(ProjectionMds, ExactEqualsPcaOnEuclideanData) {
  // Classical MDS of Euclidean distances is PCA: same scores up to each axis's sign.
  const Table t = test::gaussian_clusters(250, 6, 3, 5.0, 8);
  const Embedding m = mds_ref(t, 3), p = pca_ref(t);
  for (int k = 0; k < 2; ++k) {
    const double sign = m.xy[k] * p.xy[k] < 0 ? -1 : 1;
    for (std::size_t i = 0; i < t.rows; ++i) EXPECT_NEAR(m.xy[2 * i + k], sign * p.xy[2 * i + k], 1e-3) << i;
  }
}

TEST(ProjectionMds, LandmarkRecoversPlanarDistances) {
  std::vector<double> truth;
  const Table t = planar(limits::kMaxExactMdsRows + 200, 5, 6, truth);
  const Embedding e = mds_ref(t, 2);
  EXPECT_EQ(e.variant, "landmark");
  EXPECT_LT(max_distance_error(t, e.xy), 1e-5);
}

TEST(ProjectionTsne, AffinitiesMatchPerplexityAndAreSymmetric) {
  const Table t = test::gaussian_clusters(200, 5, 3, 8.0, 12);
  const Knn g = knn_ref(t, 30);
  // The brute-force reference itself, checked on one row by a full sort.
  for (std::size_t i : {0u, 77u, 199u}) {
    std::vector<std::pair<double, int>> all;
    for (std::size_t j = 0; j < t.rows; ++j)
      if (j != i) {
        double s = 0;
        for (std::size_t c = 0; c < t.cols; ++c)
          s += (double(t.at(i, c)) - t.at(j, c)) * (double(t.at(i, c)) - t.at(j, c));
        all.emplace_back(s, static_cast<int>(j));
      }
    std::sort(all.begin(), all.end());
    for (int a = 0; a < 30; ++a) EXPECT_EQ(g.idx[i * 30 + a], all[a].second);
  }
  const Affinities p = tsne_affinities(g, 10.0);
  double sum = 0;
  for (double v : p.p) sum += v;
  EXPECT_NEAR(sum, 1.0, 1e-12);
  // Symmetric: p_ij == p_ji.
  for (std::size_t i = 0; i < p.rows; ++i)
    for (std::int64_t e = p.row_start[i]; e < p.row_start[i + 1]; ++e) {
      const std::size_t j = static_cast<std::size_t>(p.col[e]);
      const auto* b = p.col.data() + p.row_start[j];
      const auto* f = std::find(b, p.col.data() + p.row_start[j + 1], static_cast<std::int32_t>(i));
      ASSERT_NE(f, p.col.data() + p.row_start[j + 1]);
      EXPECT_DOUBLE_EQ(p.p[e], p.p[p.row_start[j] + (f - b)]);
    }
  // Against an independent calibration: bisection on log β over (1e-8, 1e8) to entropy log 10 for every
  // row, then 2N·P_ij must equal p(j|i) + p(i|j). Both stop within 1e-5 nats of the target entropy, which
  // moves the probabilities by well under 1e-3 relative.
  const std::size_t n = g.rows;
  std::vector<double> cond(n * 30);
  for (std::size_t i = 0; i < n; ++i) {
    double lo = std::log(1e-8), hi = std::log(1e8);
    for (int it = 0; it < 100; ++it) {
      const double beta = std::exp(0.5 * (lo + hi));
      double s = 0, h = 0;
      for (int a = 0; a < 30; ++a) s += std::exp(-beta * (g.sqdist[i * 30 + a] - g.sqdist[i * 30]));
      for (int a = 0; a < 30; ++a) {
        const double q = std::exp(-beta * (g.sqdist[i * 30 + a] - g.sqdist[i * 30])) / s;
        cond[i * 30 + a] = q;
        if (q > 0) h -= q * std::log(q);
      }
      (h > std::log(10.0) ? lo : hi) = std::log(beta);
    }
  }
  const auto cond_of = [&](std::size_t i, std::size_t j) {
    for (int a = 0; a < 30; ++a)
      if (static_cast<std::size_t>(g.idx[i * 30 + a]) == j) return cond[i * 30 + a];
    return 0.0;
  };
  for (std::size_t i = 0; i < n; ++i)
    for (std::int64_t e = p.row_start[i]; e < p.row_start[i + 1]; ++e) {
      const std::size_t j = static_cast<std::size_t>(p.col[e]);
      const double expect = cond_of(i, j) + cond_of(j, i);
      EXPECT_NEAR(p.p[e] * 2.0 * double(n), expect, 1e-3 * expect + 1e-12) << i << "," << j;
    }
}

TEST(ProjectionTsne, BarnesHutGradientApproximatesExact) {
  const Table t = test::gaussian_clusters(800, 10, 4, 6.0, 5);
  const Affinities p = tsne_affinities(knn_ref(t, 45), 15.0);
  std::vector<double> y(2 * t.rows);
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0, 5);
  for (double& v : y) v = g(rng);
  const std::vector<double> exact = tsne_gradient_ref(p, y, 1.0, 0.0);
  const std::vector<double> bh = tsne_gradient_ref(p, y, 1.0, 0.5);
  double num = 0, den = 0;
  for (std::size_t c = 0; c < y.size(); ++c)
    num += (exact[c] - bh[c]) * (exact[c] - bh[c]), den += exact[c] * exact[c];
  // θ = 0.5 keeps the relative error of the whole gradient around 1% (van der Maaten 2014).
  EXPECT_LT(std::sqrt(num / den), 0.03);
  // θ → small approaches the exact sum.
  const std::vector<double> fine = tsne_gradient_ref(p, y, 1.0, 0.05);
  num = 0;
  for (std::size_t c = 0; c < y.size(); ++c) num += (exact[c] - fine[c]) * (exact[c] - fine[c]);
  EXPECT_LT(std::sqrt(num / den), 1e-3);
}

double neighbourhood_hit(const std::vector<double>& xy, const std::vector<int>& labels, int k) {
  const std::size_t n = labels.size();
  double hit = 0;
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<std::pair<double, std::size_t>> d;
    for (std::size_t j = 0; j < n; ++j)
      if (j != i) d.emplace_back(test::dist2d(xy, i, j), j);
    std::partial_sort(d.begin(), d.begin() + k, d.end());
    for (int a = 0; a < k; ++a) hit += labels[d[a].second] == labels[i];
  }
  return hit / double(n * k);
}

TEST(ProjectionTsne, SeparatesClustersAndIsDeterministic) {
  std::vector<int> labels;
  const Table t = test::gaussian_clusters(700, 20, 5, 12.0, 31, &labels);  // FFT (N > 500)
  TsneOptions o;
  o.perplexity = 20;
  o.iterations = 400;
  const Embedding a = tsne_ref(t, o);
  EXPECT_EQ(a.variant, "fft");
  EXPECT_GT(neighbourhood_hit(a.xy, labels, 10), 0.98);
  QualityOptions qo;
  qo.backend = Backend::cpu;
  EXPECT_GT(quality_ref(t, a.xy, qo).trustworthiness, 0.9);
  const Embedding b = tsne_ref(t, o);
  EXPECT_EQ(a.xy, b.xy);  // same seed, same bits
}

TEST(ProjectionTsne, ExactSmallSeparates) {
  std::vector<int> labels;
  const Table t = test::gaussian_clusters(240, 8, 3, 10.0, 2, &labels);
  TsneOptions o;
  o.perplexity = 15;
  o.iterations = 300;
  const Embedding e = tsne_ref(t, o);
  EXPECT_EQ(e.variant, "exact");
  EXPECT_GT(neighbourhood_hit(e.xy, labels, 10), 0.98);
}

TEST(ProjectionForce, ReducesStressTowardsAnIsometry) {
  std::vector<double> truth;
  const Table t = planar(150, 6, 9, truth);
  QualityOptions qo;
  qo.backend = Backend::cpu;
  const double s5 = quality_ref(t, force_scheme_ref(t, 5, 1).xy, qo).stress;
  const double s300 = quality_ref(t, force_scheme_ref(t, 300, 1).xy, qo).stress;
  EXPECT_LT(s300, s5);  // a Guttman step never increases the raw stress
  EXPECT_LT(s300, 0.02);
}

TEST(ProjectionLamp, IsometricDataWithTrueControlsIsExact) {
  // With every control at its true 2D position, each local orthogonal map is the isometry itself.
  std::vector<double> truth;
  const Table t = planar(400, 8, 12, truth);
  std::vector<std::size_t> controls;
  std::vector<double> cxy;
  for (std::size_t i = 0; i < t.rows; i += 17)
    controls.push_back(i), cxy.push_back(truth[2 * i]), cxy.push_back(truth[2 * i + 1]);
  const std::vector<double> xy = lamp_map_ref(t, controls, cxy);
  for (std::size_t i = 0; i < t.rows; ++i) {
    EXPECT_NEAR(xy[2 * i], truth[2 * i], 2e-5) << i;
    EXPECT_NEAR(xy[2 * i + 1], truth[2 * i + 1], 2e-5) << i;
  }
  // Control points land exactly on their positions.
  EXPECT_EQ(xy[0], cxy[0]);
  EXPECT_EQ(xy[2 * 17 + 1], cxy[3]);
}

TEST(ProjectionLamp, WholeMethodKeepsNeighbourhoods) {
  std::vector<int> labels;
  const Table t = test::gaussian_clusters(900, 10, 4, 10.0, 14, &labels);
  const Embedding e = lamp_ref(t, 5);
  EXPECT_EQ(e.variant, "controls=30");
  EXPECT_GT(neighbourhood_hit(e.xy, labels, 10), 0.95);
}

Error project_error(const Table& t, ProjectOptions o) {
  try {
    (void)project(t, o);
  } catch (const Error& e) {
    return e;
  }
  return Error(Error::Kind::internal, "", "no error");
}

// openTSNE's rule for small tables: the perplexity is capped at (N − 1) / 3 and the answer says so. The
// capped run is the same as asking tsne() for that perplexity directly (tsne() itself still refuses a
// perplexity its table cannot hold).
TEST(ProjectionOptions, TsnePerplexityCappedForSmallTables) {
  const Table t = test::gaussian_clusters(20, 4, 2, 5.0, 1);
  EXPECT_DOUBLE_EQ(effective_perplexity(30, 20), 19.0 / 3.0);
  EXPECT_DOUBLE_EQ(effective_perplexity(5, 20), 5.0);
  ProjectOptions o;
  o.backend = Backend::cpu;
  o.method = Method::tsne;
  o.perplexity = 30;
  o.standardize = false;
  const Embedding e = project(t, o);
  EXPECT_DOUBLE_EQ(e.perplexity, 19.0 / 3.0);
  TsneOptions to;
  to.perplexity = 19.0 / 3.0;
  const Embedding direct = tsne(t, to, Backend::cpu);
  EXPECT_EQ(e.xy, direct.xy);
  to.perplexity = 30;
  EXPECT_THROW((void)tsne(t, to, Backend::cpu), Error);
  // Other methods report none.
  o.method = Method::pca;
  EXPECT_TRUE(std::isnan(project(t, o).perplexity));
}

TEST(ProjectionOptions, BadOptionsGiveExactErrors) {
  const Table t = test::gaussian_clusters(60, 4, 2, 5.0, 1);
  ProjectOptions o;
  o.backend = Backend::cpu;
  o.method = Method::tsne;
  o.perplexity = 30;
  Error e = project_error(test::gaussian_clusters(3, 1, 2, 5.0, 1), o);
  EXPECT_EQ(e.param(), "table");
  EXPECT_STREQ(e.what(), "t-SNE needs at least 4 rows (perplexity ≥ 1 needs 3 neighbours); the table has 3");
  o.perplexity = 0.5;
  EXPECT_STREQ(project_error(t, o).what(), "perplexity must be in [1, 100], not 0.500000");
  o.perplexity = 5;
  o.iterations = -1;
  e = project_error(t, o);
  EXPECT_EQ(e.param(), "iterations");
  o.iterations = 0;
  o.theta = 2;
  EXPECT_EQ(project_error(t, o).param(), "theta");
  try {
    (void)parse_method("umap");
    FAIL();
  } catch (const Error& x) {
    EXPECT_EQ(x.param(), "method");
    EXPECT_STREQ(x.what(), "method must be one of pca, mds, tsne, force, lamp, not 'umap'");
  }
  Table big = test::gaussian_clusters(limits::kMaxForceSchemeRows + 1, 1, 1, 1.0, 1);
  o = ProjectOptions{};
  o.method = Method::force;
  e = project_error(big, o);
  EXPECT_EQ(e.kind(), Error::Kind::payload_too_large);
  EXPECT_EQ(e.param(), "table");
  try {
    (void)lamp_map_ref(t, {0}, {0, 0});
    FAIL();
  } catch (const Error& x) {
    EXPECT_EQ(x.param(), "controls");
  }
}

TEST(ProjectionOptions, ProjectStandardisesFirst) {
  // A column scaled by 1000 dominates raw PCA; after z-scoring both columns weigh the same.
  Table t = test::gaussian_clusters(100, 2, 1, 0.0, 4);
  for (std::size_t r = 0; r < t.rows; ++r) t.values[r * 2] *= 1000;
  ProjectOptions o;
  o.backend = Backend::cpu;
  Table z = t;
  standardize(z);
  EXPECT_EQ(project(t, o).xy, pca_ref(z).xy);
  o.standardize = false;
  EXPECT_EQ(project(t, o).xy, pca_ref(t).xy);
}

}  // namespace
}  // namespace trailscope::projection
