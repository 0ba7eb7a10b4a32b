// Reference versus OpenCL for every projection method and the quality metrics: the same public call
// with the backend switched, in strict mode so that a silent fallback cannot make a comparison pass.
// The device computes in float and the references in double, so each comparison has a tolerance,
// justified where it is used.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "strict_opencl.hpp"
#include "projection_test_util.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/ocl_info.hpp"
#include "trailscope/projection/projection.hpp"
#include "trailscope/projection/quality.hpp"

namespace trailscope::projection {
namespace {

class ProjectionOcl : public trailscope::test::StrictOpenCl {};

TEST_F(ProjectionOcl, KnnMatchesReference) {
  const Table t = test::gaussian_clusters(1500, 30, 6, 4.0, 3);
  const Knn a = knn(t, 45, Backend::opencl), b = knn_ref(t, 45);
  // Float distances may swap two neighbours whose squared distances agree to ~1e-7 relative, so compare
  // sets with a tolerance of 1 in 1000 and distances to 1e-4 relative.
  std::size_t same = 0;
  for (std::size_t i = 0; i < t.rows; ++i) {
    std::set<int> sa(a.idx.begin() + i * 45, a.idx.begin() + (i + 1) * 45);
    for (int x = 0; x < 45; ++x) same += sa.count(b.idx[i * 45 + x]);
    for (int x = 0; x < 45; ++x)
      EXPECT_NEAR(a.sqdist[i * 45 + x], b.sqdist[i * 45 + x], 1e-4 * b.sqdist[i * 45 + x]);
  }
  EXPECT_GE(double(same) / double(t.rows * 45), 0.999);
}

TEST_F(ProjectionOcl, PcaMatchesReference) {
  const Table t = test::gaussian_clusters(3000, 40, 5, 5.0, 4);
  const Embedding o = pca(t, Backend::opencl), r = pca_ref(t);
  EXPECT_EQ(o.path, "opencl");
  // Float partial sums of ≤ 64-row chunks and float scores: ~1e-6 relative; the eigenvector error is that
  // over the eigen-gap of well-separated clusters, so 1e-4 of the layout's extent has ample margin.
  EXPECT_LT(test::rel_diff(o.xy, r.xy), 1e-4);
}

TEST_F(ProjectionOcl, ExactMdsMatchesReference) {
  const Table t = test::gaussian_clusters(900, 16, 4, 6.0, 6);
  const Embedding o = mds(t, 1, Backend::opencl), r = mds_ref(t, 1);
  EXPECT_EQ(o.variant, "exact");
  // Both stop at a residual of 1e-5·λ1 (detail::kEigenTol); B in float adds ~1e-6: coordinates agree
  // to ~1e-4 of the extent, checked at 1e-3.
  EXPECT_LT(test::rel_diff(o.xy, r.xy), 1e-3);
}

TEST_F(ProjectionOcl, LandmarkMdsMatchesReference) {
  const Table t = test::gaussian_clusters(limits::kMaxExactMdsRows + 500, 10, 4, 6.0, 7);
  const Embedding o = mds(t, 1, Backend::opencl), r = mds_ref(t, 1);
  EXPECT_EQ(o.variant, "landmark");
  // Float squared distances (~1e-7 relative) through the landmark triangulation, whose pseudo-inverse
  // has a condition number of ~λ1/λ2: 1e-4 of the extent.
  EXPECT_LT(test::rel_diff(o.xy, r.xy), 1e-4);
}

TEST_F(ProjectionOcl, TsneGradientMatchesReference) {
  const Table t = test::gaussian_clusters(1200, 10, 4, 6.0, 8);
  const Affinities p = tsne_affinities(knn_ref(t, 60), 20.0);
  std::vector<double> y(2 * t.rows);
  std::mt19937 rng(1);
  std::normal_distribution<double> g(0, 4);
  for (double& v : y) v = g(rng);
  for (double theta : {0.0, 0.5}) {
    const std::vector<double> o = tsne_gradient(p, y, 12.0, theta, Backend::opencl);
    const std::vector<double> r = tsne_gradient_ref(p, y, 12.0, theta);
    // Float sums of ≤ 1200 terms (exact) or a few hundred cells (Barnes-Hut, whose opening decisions
    // can flip for cells at exactly side/d = θ in float): 1e-3 of the largest component.
    EXPECT_LT(test::rel_diff(o, r), 1e-3) << "theta " << theta;
  }
}

TEST_F(ProjectionOcl, TsneFftRepulsionMatchesReference) {
  // Same grid, same interpolation: the device's float spread/gather and the host's float FFT against
  // the double reference. Float rounding of coordinates ~30 and of sums of ~400 terms: 1e-4 relative.
  std::mt19937 rng(5);
  std::normal_distribution<double> g(0, 6);
  std::vector<double> y(2 * 1200);
  for (double& v : y) v = g(rng);
  for (int p : {3, 5}) {
    TsneFftOptions f;
    f.nodes_per_box = p;
    const std::vector<double> o = tsne_repulsion_fft(y, f, Backend::opencl), r = tsne_repulsion_fft_ref(y, f);
    EXPECT_LT(test::rel_diff(o, r), 1e-4) << "p " << p;
  }
}

TEST_F(ProjectionOcl, TsneFftGradientMatchesReference) {
  const Table t = test::gaussian_clusters(900, 16, 5, 6.0, 12);
  const Affinities p = tsne_affinities(knn_ref(t, 60), 20.0);
  std::mt19937 rng(8);
  std::normal_distribution<double> g(0, 4);
  std::vector<double> y(2 * t.rows);
  for (double& v : y) v = g(rng);
  for (double ex : {1.0, 12.0}) {
    const std::vector<double> o = tsne_gradient_fft(p, y, ex, TsneFftOptions{}, Backend::opencl);
    const std::vector<double> r = tsne_gradient_fft_ref(p, y, ex, TsneFftOptions{});
    EXPECT_LT(test::rel_diff(o, r), 1e-3) << "exaggeration " << ex;
  }
}

TEST_F(ProjectionOcl, TsneMatchesReferenceQuality) {
  // The optimisation is chaotic: float and double trajectories part after a few hundred steps, so the
  // two runs are compared by what they must share, the quality of the result, not coordinates.
  std::vector<int> labels;
  const Table t = test::gaussian_clusters(1000, 20, 6, 10.0, 9, &labels);
  for (TsneRepulsion rep : {TsneRepulsion::automatic, TsneRepulsion::barnes_hut}) {
    TsneOptions to;
    to.perplexity = 20;
    to.iterations = 300;
    to.repulsion = rep;
    const Embedding o = tsne(t, to, Backend::opencl), r = tsne_ref(t, to);
    EXPECT_EQ(o.path, "opencl");
    EXPECT_EQ(o.variant, rep == TsneRepulsion::automatic ? "fft" : "barnes-hut");
    QualityOptions qo;
    qo.backend = Backend::cpu;
    const double to_ = quality_ref(t, o.xy, qo).trustworthiness,
                 tr = quality_ref(t, r.xy, qo).trustworthiness;
    EXPECT_GT(to_, 0.9) << o.variant;
    EXPECT_NEAR(to_, tr, 0.01) << o.variant;
    EXPECT_EQ(tsne(t, to, Backend::opencl).xy, o.xy) << o.variant;  // deterministic on the device too
  }
}

TEST_F(ProjectionOcl, ForceSchemeMatchesReference) {
  const Table t = test::gaussian_clusters(400, 8, 3, 6.0, 10);
  const Embedding o = force_scheme(t, 50, 3, Backend::opencl), r = force_scheme_ref(t, 50, 3);
  // Same start; each Guttman step is a contraction towards the same local minimum, so float rounding
  // (~1e-6 per step) stays ~1e-4 of the extent after 50 steps.
  EXPECT_LT(test::rel_diff(o.xy, r.xy), 1e-3);
}

TEST_F(ProjectionOcl, LampMapMatchesReference) {
  const Table t = test::gaussian_clusters(2000, 12, 5, 6.0, 11);
  const std::vector<std::size_t> controls = {3, 50, 77, 200, 431, 999, 1500, 1777, 1999, 1234};
  std::vector<double> cxy;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-10, 10);
  for (std::size_t i = 0; i < 2 * controls.size(); ++i) cxy.push_back(u(rng));
  const std::vector<double> o = lamp_map(t, controls, cxy, Backend::opencl),
                            r = lamp_map_ref(t, controls, cxy);
  // SVD (reference) against the closed-form polar factor in float: the 2×2 inverse square root loses
  // ~1e-6·σ1/σ2 relative; 1e-3 of the extent.
  EXPECT_LT(test::rel_diff(o, r), 1e-3);
  // Control points take their positions, as the device stores them (float).
  for (std::size_t c = 0; c < controls.size(); ++c)
    EXPECT_EQ(static_cast<float>(o[2 * controls[c]]), static_cast<float>(cxy[2 * c]));
}

TEST_F(ProjectionOcl, LampMatchesReference) {
  const Table t = test::gaussian_clusters(2500, 12, 5, 6.0, 12);
  const Embedding o = lamp(t, 2, Backend::opencl), r = lamp_ref(t, 2);
  EXPECT_EQ(o.path, "opencl");
  // The control layout comes from 100 Force Scheme steps in float versus double (above), then the map:
  // 1e-2 of the extent.
  EXPECT_LT(test::rel_diff(o.xy, r.xy), 1e-2);
}

TEST_F(ProjectionOcl, QualityMatchesReference) {
  const Table t = test::gaussian_clusters(2500, 10, 5, 6.0, 13);
  const Embedding e = pca_ref(t);
  QualityOptions qo;
  qo.k = 10;
  qo.sample = 800;
  qo.backend = Backend::opencl;
  const Quality o = quality(t, e.xy, qo), r = quality_ref(t, e.xy, qo);
  EXPECT_EQ(o.path, "opencl");
  EXPECT_TRUE(o.sampled);
  // Same queries; float distances can only reorder near-ties: 1e-3.
  EXPECT_NEAR(o.trustworthiness, r.trustworthiness, 1e-3);
  EXPECT_NEAR(o.continuity, r.continuity, 1e-3);
  EXPECT_NEAR(o.neighborhood_preservation, r.neighborhood_preservation, 1e-3);
  EXPECT_NEAR(o.stress, r.stress, 1e-5);
  EXPECT_NEAR(o.shepard, r.shepard, 1e-4);
}

TEST_F(ProjectionOcl, InjectedFailureFallsBackOrThrowsInStrictMode) {
  const Table t = test::gaussian_clusters(100, 5, 2, 5.0, 14);
  test::ScopedEnv inject("TRAILSCOPE_OPENCL_INJECT_FAILURE", "projection_pca");
  try {
    (void)pca(t, Backend::opencl);
    FAIL() << "strict mode must forbid the fallback";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::backend);
    EXPECT_NE(std::string(e.what()).find("projection_pca"), std::string::npos);
  }
  test::ScopedEnv lax("TRAILSCOPE_OPENCL_STRICT", "0");
  const Embedding e = pca(t, Backend::opencl);
  EXPECT_EQ(e.path, "cpu");
  EXPECT_EQ(e.xy, pca_ref(t).xy);
  const OpPathStats s = op_path_stats("projection_pca");
  EXPECT_GE(s.fallbacks, 1u);
}

}  // namespace
}  // namespace trailscope::projection
