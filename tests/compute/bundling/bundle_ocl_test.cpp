// OpenCL versus the C++ reference for every bundling step and the whole loop, in strict mode so that a
// silent fallback cannot pass. Tolerance: none — the kernels repeat the reference's operations (double
// geometry, integer density), so the points must be the same bits.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "strict_opencl.hpp"
#include "../../../compute/src/bundling/steps.hpp"
#include "../../../compute/src/bundling/bundle_ocl.hpp"
#include "trailscope/bundling/bundle.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/ocl_info.hpp"

namespace trailscope::bundling {
namespace {
using detail::Points;

class BundleOcl : public test::StrictOpenCl {};

// Random polylines of 2..max_points points in [lo, hi)², some of them leaving the image.
Points random_points(std::mt19937& rng, int polylines, int max_points, float lo, float hi) {
  std::uniform_real_distribution<float> pos(lo, hi), z(0, 1);
  std::uniform_int_distribution<int> len(2, max_points);
  Points p;
  for (int e = 0; e < polylines; ++e) {
    const int n = len(rng);
    float x = pos(rng), y = pos(rng);
    for (int i = 0; i < n; ++i) {
      p.x.push_back(x), p.y.push_back(y), p.z.push_back(i % 5 == 0 ? 0.0f : z(rng));
      p.edge.push_back(static_cast<std::uint32_t>(e));
      x += pos(rng) * 0.1f - (hi + lo) * 0.05f, y += pos(rng) * 0.1f - (hi + lo) * 0.05f;
    }
    p.offsets.push_back(static_cast<std::uint32_t>(p.x.size()));
  }
  return p;
}

void expect_same(const Points& a, const Points& b) {
  ASSERT_EQ(a.offsets, b.offsets);
  ASSERT_EQ(a.size(), b.size());
  std::size_t diff = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    diff += a.x[i] != b.x[i] || a.y[i] != b.y[i] || a.z[i] != b.z[i] || a.edge[i] != b.edge[i];
  EXPECT_EQ(diff, 0u) << "of " << a.size() << " points";
}

TEST_F(BundleOcl, ResampleIsBitIdentical) {
  std::mt19937 rng(11);
  for (Profile profile : {Profile::uniform, Profile::hourglass})
    for (bool block : {true, false}) {
      const Points in = random_points(rng, 500, 12, -20, 300);
      const std::vector<float> table = detail::profile_table(profile);
      detail::ResampleArgs a;
      a.spl = 7.3, a.jitter = 0.4, a.seed = 12345, a.iteration = 3, a.block_endpoints = block;
      a.profile = table.data();
      const Points ref = detail::resample(in, a);
      Points ocl;
      ASSERT_EQ(ocl::bundle_resample_ocl(in, a, ocl), "");
      expect_same(ref, ocl);
    }
}

TEST_F(BundleOcl, SplatAndConvolutionAreBitIdentical) {
  std::mt19937 rng(12);
  for (int radius : {2, 8, 32, 128}) {
    const int size = 200;
    const Points p = random_points(rng, 300, 20, -10, 210);
    std::vector<std::uint32_t> weights(p.edges());
    for (auto& w : weights) w = rng() % 1024 + 1;
    std::vector<std::uint32_t> img(size * size);
    const detail::Box box = detail::splat(p, weights, size, img);
    std::vector<std::uint64_t> rows(size * size);
    std::vector<float> dens(size * size);
    detail::convolve(img, size, box, radius, rows, dens);
    std::vector<std::uint32_t> oimg;
    std::vector<float> odens;
    detail::Box obox;
    ASSERT_EQ(ocl::bundle_density_ocl(p, weights, size, radius, oimg, obox, odens), "");
    EXPECT_EQ(oimg, img);
    EXPECT_EQ(obox.x0, box.x0);
    EXPECT_EQ(obox.y0, box.y0);
    EXPECT_EQ(obox.x1, box.x1);
    EXPECT_EQ(obox.y1, box.y1);
    const detail::Box r = detail::read_region(box, size);
    std::size_t diff = 0;
    for (int y = r.y0; y <= r.y1; ++y)
      for (int x = r.x0; x <= r.x1; ++x) diff += dens[y * size + x] != odens[y * size + x];
    EXPECT_EQ(diff, 0u) << "radius " << radius;
  }
}

// Many points on a small image: on a CPU device the splat then runs as several private images summed
// (bundle_ocl.cpp splat_private: one part per image's worth of points, up to one per compute unit), and
// the loop's later splats must find the partial images cleared.
TEST_F(BundleOcl, DenseSplatIsBitIdentical) {
  std::mt19937 rng(16);
  const int size = 24;
  const Points p = random_points(rng, 2000, 12, -2, 26);
  ASSERT_GT(p.size(), 8u * size * size);
  std::vector<std::uint32_t> weights(p.edges());
  for (auto& w : weights) w = rng() % 1024 + 1;
  std::vector<std::uint32_t> img(size * size);
  const detail::Box box = detail::splat(p, weights, size, img);
  std::vector<std::uint64_t> rows(size * size);
  std::vector<float> dens(size * size);
  detail::convolve(img, size, box, 4, rows, dens);
  std::vector<std::uint32_t> oimg;
  std::vector<float> odens;
  detail::Box obox;
  ASSERT_EQ(ocl::bundle_density_ocl(p, weights, size, 4, oimg, obox, odens), "");
  EXPECT_EQ(oimg, img);
  EXPECT_EQ(obox.x0, box.x0);
  EXPECT_EQ(obox.y1, box.y1);
  EXPECT_EQ(odens, dens);  // the box covers the image: every value is written

  // The whole loop on a small image with many points: several iterations of splats.
  std::uniform_real_distribution<double> u(0, 100);
  Polylines src;
  for (int e = 0; e < 3000; ++e) src.add_edge(u(rng), u(rng), u(rng), u(rng));
  BundleParams bp;
  bp.size = 64, bp.h = 8, bp.spl = 2, bp.iterations = 4;
  const Frame f = Frame::fit(src, bp.size, bp.border, true);
  const Polylines px = f.to_pixels(src);
  const Bundled ref = bundle_ref(px, f, bp);
  const Bundled dev = bundle(px, f, bp, Backend::opencl);
  ASSERT_GT(ref.lines.points(), 8u * 64 * 64);
  EXPECT_EQ(ref.lines.x, dev.lines.x);
  EXPECT_EQ(ref.lines.y, dev.lines.y);
}

TEST_F(BundleOcl, AdvectIsBitIdentical) {
  std::mt19937 rng(13);
  const int size = 256;
  Points p = random_points(rng, 400, 15, -5, 260);
  std::vector<std::uint32_t> img(size * size);
  const detail::Box box = detail::splat(p, std::vector<std::uint32_t>(p.edges(), 3), size, img);
  std::vector<std::uint64_t> rows(size * size);
  std::vector<float> dens(size * size);
  detail::convolve(img, size, box, 12, rows, dens);
  Points ref = p, dev = p;
  detail::advect(ref, dens, size, 0.5 * 12.7);
  ASSERT_EQ(ocl::bundle_advect_ocl(dev, dens, size, 0.5 * 12.7), "");
  expect_same(ref, dev);
  EXPECT_NE(ref.x, p.x);  // something moved
}

TEST_F(BundleOcl, SmoothIsBitIdentical) {
  std::mt19937 rng(14);
  for (int passes : {1, 2, 3}) {
    const Points p = random_points(rng, 300, 30, 0, 500);
    Points ref = p, dev = p;
    detail::smooth(ref, 3, 0.35, passes);
    ASSERT_EQ(ocl::bundle_smooth_ocl(dev, 3, 0.35, passes), "");
    expect_same(ref, dev);
  }
}

Polylines random_graph(std::mt19937& rng, int edges, double extent) {
  std::uniform_real_distribution<double> u(0, extent);
  std::vector<std::pair<double, double>> nodes(30);
  for (auto& n : nodes) n = {u(rng), u(rng) * 0.7};
  std::uniform_int_distribution<int> pick(0, 29);
  Polylines p;
  for (int e = 0; e < edges; ++e) {
    const auto a = nodes[pick(rng)], b = nodes[pick(rng)];
    p.add_edge(a.first, a.second, b.first, b.second);
  }
  // A trail of several points too.
  p.add(std::vector<double>{10, 200, 400, 600}, std::vector<double>{10, 300, 20, 400});
  return p;
}

TEST_F(BundleOcl, WholeBundleIsBitIdentical) {
  std::mt19937 rng(15);
  const Polylines src = random_graph(rng, 300, 1000);
  std::vector<BundleParams> variants(5);
  variants[4].size = 128, variants[4].directional = true, variants[4].repulsion = 2,
  variants[4].iterations = 6;
  variants[0].size = 256, variants[0].h = 24;
  variants[1].size = 200, variants[1].profile = Profile::hourglass, variants[1].density = DensityMode::count,
  variants[1].smooth_iterations = 3, variants[1].smooth_kernel = 0.15, variants[1].iterations = 6;
  variants[2].size = 128, variants[2].polyline_style = true, variants[2].block_endpoints = false,
  variants[2].jitter = 1, variants[2].seed = 77, variants[2].spl = 4;
  variants[3].size = 256, variants[3].ms_iterations = 5, variants[3].dir_separation = 2,
  variants[3].relaxation = 0.3;
  for (const BundleParams& p : variants) {
    const Frame f = Frame::fit(src, p.size, p.border, true);
    const Polylines px = f.to_pixels(src);
    const Bundled ref = bundle_ref(px, f, p);
    const Bundled dev = bundle(px, f, p, Backend::opencl);
    EXPECT_EQ(dev.path, "opencl");
    EXPECT_EQ(dev.device, opencl_info().device);
    EXPECT_EQ(ref.lines.offsets, dev.lines.offsets);
    EXPECT_EQ(ref.lines.x, dev.lines.x);
    EXPECT_EQ(ref.lines.y, dev.lines.y);
    EXPECT_EQ(ref.quality.ink_bundled_px, dev.quality.ink_bundled_px);
    if (!p.directional) EXPECT_LT(dev.quality.ink_bundled_px, dev.quality.ink_raw_px);
  }
}

TEST_F(BundleOcl, AFailingDeviceFallsBackOrThrowsInStrictMode) {
  std::mt19937 rng(17);
  BundleParams p;
  p.size = 128;
  const Polylines src = random_graph(rng, 40, 100);
  const Frame f = Frame::fit(src, p.size, p.border);
  const Polylines px = f.to_pixels(src);
  const test::ScopedEnv inject("TRAILSCOPE_OPENCL_INJECT_FAILURE", "bundle");
  try {
    bundle(px, f, p, Backend::opencl);
    ADD_FAILURE() << "strict mode let a fallback through";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::backend) << e.what();
  }
  const test::ScopedEnv lenient("TRAILSCOPE_OPENCL_STRICT", "0");
  const Bundled b = bundle(px, f, p, Backend::opencl);
  EXPECT_EQ(b.path, "cpu");
  EXPECT_EQ(b.lines.x, bundle_ref(px, f, p).lines.x);
  const OpPathStats stats = op_path_stats("bundle");
  EXPECT_GT(stats.fallbacks, 0u);
  EXPECT_EQ(stats.last_path, "cpu");
}

TEST_F(BundleOcl, CancellationAndLimitsAreAnswersNotFallbacks) {
  std::mt19937 rng(16);
  BundleParams p;
  p.size = 128;
  const Polylines src = random_graph(rng, 50, 100);
  const Frame f = Frame::fit(src, p.size, p.border);
  const Polylines px = f.to_pixels(src);
  CancelToken token;
  int n = 0;
  try {
    bundle(
        px, f, p, Backend::opencl,
        [&](double, std::string_view) {
          if (++n == 2) token.cancel();
        },
        &token);
    FAIL() << "not cancelled";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::cancelled) << e.what();
  }
  EXPECT_EQ(n, 2);
  Polylines huge;
  huge.add_edge(0, 0, 1e9, 0);
  p.spl = 1;
  try {
    bundle(huge, f, p, Backend::opencl);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::payload_too_large) << e.what();
  }
}

}  // namespace
}  // namespace trailscope::bundling
