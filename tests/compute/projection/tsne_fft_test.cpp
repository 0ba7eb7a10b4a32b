// The FFT-interpolated t-SNE repulsion (FIt-SNE) of the C++ reference against the exact O(N²) sums, its
// convergence as the grid is refined, the whole gradient against the exact one, the kNN against brute
// force, and the whole t-SNE on clustered data with the FFT variant.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "projection_test_util.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/projection/projection.hpp"
#include "trailscope/projection/quality.hpp"

namespace trailscope::projection {
namespace {

std::vector<double> gaussian_layout(std::size_t n, double sd, std::uint64_t seed) {
  std::mt19937 rng(static_cast<unsigned>(seed));
  std::normal_distribution<double> g(0, sd);
  std::vector<double> y(2 * n);
  for (double& v : y) v = g(rng);
  return y;
}

// Largest error of the forces (both components) and of the per-point Z sums, each relative to the
// largest exact value of its kind.
struct Errors {
  double force = 0, z = 0;
};
Errors errors(const std::vector<double>& got, const std::vector<double>& exact) {
  double ef = 0, sf = 0, ez = 0, sz = 0;
  for (std::size_t i = 0; i < exact.size() / 3; ++i) {
    for (int c = 0; c < 2; ++c)
      ef = std::max(ef, std::abs(got[3 * i + c] - exact[3 * i + c])),
      sf = std::max(sf, std::abs(exact[3 * i + c]));
    ez = std::max(ez, std::abs(got[3 * i + 2] - exact[3 * i + 2])),
    sz = std::max(sz, std::abs(exact[3 * i + 2]));
  }
  return {ef / sf, ez / sz};
}

TEST(TsneFft, RepulsionMatchesExactSumsOnAFineGrid) {
  // 400 points spread over ~30 units (a late-phase embedding) and over ~6 (an early one).
  for (double sd : {5.0, 1.0}) {
    const std::vector<double> y = gaussian_layout(400, sd, 3);
    const std::vector<double> exact = tsne_repulsion_exact_ref(y);
    TsneFftOptions f;
    f.nodes_per_box = 4, f.box_width = 0.25, f.min_boxes = 1, f.max_boxes = 512;
    const Errors e = errors(tsne_repulsion_fft_ref(y, f), exact);
    EXPECT_LT(e.force, 1e-4) << "sd " << sd;
    EXPECT_LT(e.z, 1e-4) << "sd " << sd;
    f.nodes_per_box = 3;  // openTSNE's order needs a finer grid for the same accuracy
    const Errors e3 = errors(tsne_repulsion_fft_ref(y, f), exact);
    EXPECT_LT(e3.force, 1e-3) << "sd " << sd;
    EXPECT_LT(e3.z, 1e-3) << "sd " << sd;
  }
}

TEST(TsneFft, ErrorShrinksAsTheGridIsRefined) {
  const std::vector<double> y = gaussian_layout(300, 4.0, 7);
  const std::vector<double> exact = tsne_repulsion_exact_ref(y);
  double last = 1e300;
  for (double width : {1.0, 0.5, 0.25}) {
    TsneFftOptions f;
    f.box_width = width, f.min_boxes = 1, f.max_boxes = 512;
    const double e = errors(tsne_repulsion_fft_ref(y, f), exact).force;
    EXPECT_LT(e, 0.5 * last) << "box width " << width;  // third order: ~8× per halving
    last = e;
  }
  // openTSNE's grid (p = 3, boxes of side ≤ 1, no cap) stays within a few percent of the largest force.
  TsneFftOptions open_tsne;
  open_tsne.max_boxes = 512;
  EXPECT_LT(errors(tsne_repulsion_fft_ref(y, open_tsne), exact).force, 0.06);
}

TEST(TsneFft, CoincidentAndTinyLayoutsStayFinite) {
  std::vector<double> y(2 * 50, 0.0);  // all points at one place: w = 1 between every pair
  const std::vector<double> r = tsne_repulsion_fft_ref(y, TsneFftOptions{});
  for (std::size_t i = 0; i < 50; ++i) {
    EXPECT_NEAR(r[3 * i], 0.0, 1e-9);
    EXPECT_NEAR(r[3 * i + 2], 49.0, 1e-6);
  }
  const std::vector<double> tiny = gaussian_layout(200, 1e-4, 1);  // the PCA initialisation's scale
  const Errors e = errors(tsne_repulsion_fft_ref(tiny, TsneFftOptions{}), tsne_repulsion_exact_ref(tiny));
  EXPECT_LT(e.force, 1e-3);
  EXPECT_LT(e.z, 1e-6);
}

TEST(TsneFft, GradientApproximatesExact) {
  const Table t = test::gaussian_clusters(800, 10, 4, 6.0, 5);
  const Affinities p = tsne_affinities(knn_ref(t, 45), 15.0);
  const std::vector<double> y = gaussian_layout(t.rows, 5.0, 3);
  const std::vector<double> exact = tsne_gradient_ref(p, y, 1.0, 0.0);
  const auto rel = [&](const TsneFftOptions& f) {
    const std::vector<double> fft = tsne_gradient_fft_ref(p, y, 1.0, f);
    double num = 0, den = 0;
    for (std::size_t c = 0; c < y.size(); ++c)
      num += (exact[c] - fft[c]) * (exact[c] - fft[c]), den += exact[c] * exact[c];
    return std::sqrt(num / den);
  };
  TsneFftOptions f;
  f.max_boxes = 512;        // openTSNE's grid: boxes of side 1 over the ~35-unit layout
  EXPECT_LT(rel(f), 0.03);  // Barnes-Hut at θ = 0.5 is allowed 0.03 on the same data
  f.box_width = 0.5;
  EXPECT_LT(rel(f), 0.005);
}

TEST(TsneFft, KnnEqualsBruteForce) {
  const Table t = test::gaussian_clusters(700, 12, 5, 3.0, 8);
  const int k = 20;
  const Knn g = knn_ref(t, k);
  for (std::size_t i = 0; i < t.rows; i += 13) {
    std::vector<std::pair<double, int>> all;
    for (std::size_t j = 0; j < t.rows; ++j) {
      if (j == i) continue;
      double s = 0;
      for (std::size_t c = 0; c < t.cols; ++c)
        s += (double(t.at(i, c)) - t.at(j, c)) * (double(t.at(i, c)) - t.at(j, c));
      all.emplace_back(s, static_cast<int>(j));
    }
    std::sort(all.begin(), all.end());
    for (int a = 0; a < k; ++a) {
      EXPECT_EQ(g.idx[i * k + a], all[a].second) << i << " " << a;
      EXPECT_FLOAT_EQ(g.sqdist[i * k + a], static_cast<float>(all[a].first));
    }
  }
}

TEST(TsneFft, WholeTsneSeparatesClusters) {
  std::vector<int> labels;
  const Table t = test::gaussian_clusters(1500, 30, 8, 8.0, 17, &labels);
  TsneOptions o;
  const Embedding e = tsne_ref(t, o);
  EXPECT_EQ(e.variant, "fft");
  QualityOptions qo;
  qo.backend = Backend::cpu;
  EXPECT_GT(quality_ref(t, e.xy, qo).trustworthiness, 0.95);
  // Cluster separation: every point's nearest layout neighbour shares its cluster, almost always.
  std::size_t same = 0;
  for (std::size_t i = 0; i < t.rows; ++i) {
    double best = 1e300;
    std::size_t arg = 0;
    for (std::size_t j = 0; j < t.rows; ++j)
      if (j != i && test::dist2d(e.xy, i, j) < best) best = test::dist2d(e.xy, i, j), arg = j;
    same += labels[arg] == labels[i];
  }
  EXPECT_GT(double(same) / double(t.rows), 0.99);
  // Barnes-Hut stays available and reaches the same quality.
  o.repulsion = TsneRepulsion::barnes_hut;
  const Embedding bh = tsne_ref(t, o);
  EXPECT_EQ(bh.variant, "barnes-hut");
  EXPECT_NEAR(quality_ref(t, bh.xy, qo).trustworthiness, quality_ref(t, e.xy, qo).trustworthiness, 0.01);
}

TEST(TsneFft, BadGridOptionsGiveExactErrors) {
  const std::vector<double> y = gaussian_layout(10, 1.0, 1);
  TsneFftOptions f;
  f.nodes_per_box = 1;
  try {
    (void)tsne_repulsion_fft_ref(y, f);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.param(), "fft");
  }
  f = TsneFftOptions{};
  f.min_boxes = 10, f.max_boxes = 5;
  EXPECT_THROW((void)tsne_repulsion_fft_ref(y, f), Error);
  f = TsneFftOptions{};
  f.box_width = 0;
  EXPECT_THROW((void)tsne_repulsion_fft_ref(y, f), Error);
}

}  // namespace
}  // namespace trailscope::projection
