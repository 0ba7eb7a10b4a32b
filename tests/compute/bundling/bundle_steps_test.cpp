// The C++ reference of each bundling step (compute/src/bundling/steps.hpp) against independent
// computations written out here: the kernel radius sequence, resampling positions, the convolution as a
// direct 2D sum, the advection step length, the Laplacian mean.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "../../../compute/src/bundling/steps.hpp"

namespace trailscope::bundling::detail {
namespace {

Points one_polyline(std::vector<float> xs, std::vector<float> ys, std::vector<float> zs = {}) {
  Points p;
  p.x = std::move(xs), p.y = std::move(ys);
  p.z = zs.empty() ? std::vector<float>(p.x.size(), 1.0f) : std::move(zs);
  p.edge.assign(p.x.size(), 0);
  p.offsets = {0, static_cast<std::uint32_t>(p.x.size())};
  return p;
}

TEST(BundleSteps, KernelRadiusDecaysFromHToAbout2Point4) {
  // Defaults: h = 32, 15 iterations, factor (2/32)^(1/15) = 0.8312.
  EXPECT_DOUBLE_EQ(iteration_h(32, 15, 0), 32.0);
  EXPECT_NEAR(iteration_h(32, 15, 1), 32 * std::pow(2.0 / 32, 1.0 / 15), 1e-12);
  const double last = iteration_h(32, 15, 14);
  EXPECT_NEAR(last, 2.0 / std::pow(2.0 / 32, 1.0 / 15), 1e-9);
  EXPECT_NEAR(last, 2.406, 1e-3);
  EXPECT_EQ(kernel_radius(32), 32);
  EXPECT_EQ(kernel_radius(last), 2);
  EXPECT_EQ(kernel_radius(7.9), 6);
  for (int i = 0; i < 15; ++i) EXPECT_EQ(kernel_radius(iteration_h(32, 15, i)) % 2, 0);
}

TEST(BundleSteps, TapsAreEpanechnikovTimesRSquared) {
  const std::vector<std::uint64_t> k = kernel_taps(4);
  ASSERT_EQ(k.size(), 9u);
  // 1 − x², x = |i/8 − 0.5|/0.5, times R² = 16.
  for (int i = 0; i < 9; ++i) {
    const double x = std::fabs(i / 8.0 - 0.5) / 0.5;
    EXPECT_DOUBLE_EQ(static_cast<double>(k[i]), 16 * (1 - x * x)) << i;
  }
  EXPECT_EQ(k[0], 0u);
  EXPECT_EQ(k[4], 16u);
}

TEST(BundleSteps, ProfileTables) {
  const std::vector<float> u = profile_table(Profile::uniform), h = profile_table(Profile::hourglass);
  ASSERT_EQ(u.size(), 1024u);
  for (float v : u) EXPECT_EQ(v, 1.0f);
  EXPECT_EQ(h[512], 1.0f);
  EXPECT_EQ(h[0], 0.0f);  // x = 1 at the very end
  // x = |i − 512|/512 > 0.7 → ((1 − x)/0.3)^4.
  const double x = (1000 - 512) / 512.0;
  EXPECT_NEAR(h[1000], std::pow((1 - x) / 0.3, 4), 1e-6);
  EXPECT_EQ(h[512 + 358], 1.0f);  // x = 0.699
}

TEST(BundleSteps, ResampleWithoutJitterPlacesSamplesEverySplPixels) {
  const Points in = one_polyline({10, 60, 60}, {20, 20, 70});  // an L of 50 + 50 px
  const std::vector<float> profile = profile_table(Profile::uniform);
  ResampleArgs a;
  a.spl = 15, a.jitter = 0, a.profile = profile.data();
  const Points out = resample(in, a);
  // Samples at 15, 30, 45 (first leg), 60, 75, 90 (second leg: 10, 25, 40 px up) plus both ends.
  const std::vector<float> ex = {10, 25, 40, 55, 60, 60, 60, 60}, ey = {20, 20, 20, 20, 30, 45, 60, 70};
  ASSERT_EQ(out.size(), ex.size());
  for (std::size_t i = 0; i < ex.size(); ++i) {
    EXPECT_FLOAT_EQ(out.x[i], ex[i]) << i;
    EXPECT_FLOAT_EQ(out.y[i], ey[i]) << i;
  }
  EXPECT_EQ(out.z.front(), 0.0f);  // block_endpoints
  EXPECT_EQ(out.z.back(), 0.0f);
  EXPECT_EQ(out.z[3], 1.0f);
  // A sample exactly at the end is not made: 90 px at spl 15 has 5 interior samples.
  const Points exact = one_polyline({0, 90}, {0, 0});
  EXPECT_EQ(resample_counts(exact, 15)[0], 7u);
  EXPECT_EQ(interior_samples(0, 15), 0u);
  EXPECT_EQ(interior_samples(14.9, 15), 0u);
  EXPECT_EQ(interior_samples(15.1, 15), 1u);
}

TEST(BundleSteps, JitterShiftsSamplesAlongTheirSegmentWithinBounds) {
  const Points in = one_polyline({0, 300}, {5, 5});
  const std::vector<float> profile = profile_table(Profile::uniform);
  ResampleArgs a;
  a.spl = 10, a.jitter = 0.5, a.seed = 99, a.profile = profile.data();
  const Points out = resample(in, a);
  ASSERT_EQ(out.size(), 31u);  // 29 interior samples + 2 ends
  double moved = 0;
  for (std::size_t m = 1; m + 1 < out.size(); ++m) {
    EXPECT_EQ(out.y[m], 5.0f);
    const double expected = 10.0 * m + jitter_unit(99, 0, 0, m) * 5.0;
    EXPECT_NEAR(out.x[m], expected, 1e-4) << m;
    moved += std::fabs(out.x[m] - 10.0 * m);
  }
  EXPECT_GT(moved, 29 * 1.0);  // on average 2.5 px
  for (std::uint64_t s = 0; s < 1000; ++s) {
    const double r = jitter_unit(7, 3, 11, s);
    EXPECT_GE(r, -1.0);
    EXPECT_LT(r, 1.0);
  }
  EXPECT_EQ(jitter_unit(7, 3, 11, 5), jitter_unit(7, 3, 11, 5));
  EXPECT_NE(jitter_unit(7, 3, 11, 5), jitter_unit(8, 3, 11, 5));
}

TEST(BundleSteps, TooManyResampledPointsIsPayloadTooLarge) {
  const Points in = one_polyline({0, 1e9f}, {0, 0});
  try {
    resample_offsets(resample_counts(in, 1.0));
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::payload_too_large);
    EXPECT_EQ(e.param(), "input");
  }
}

TEST(BundleSteps, ConvolutionEqualsTheDirect2DSum) {
  const int size = 64, radius = 6;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> pos(-3, size + 3);
  Points p;
  for (int i = 0; i < 400; ++i) {
    p.x.push_back(pos(rng) * 0.5f + 10), p.y.push_back(pos(rng) * 0.6f + 4);
    p.z.push_back(1), p.edge.push_back(i % 7);
  }
  p.x.push_back(1.5f), p.y.push_back(62.2f), p.z.push_back(1), p.edge.push_back(3);  // near the border
  p.offsets = {0, static_cast<std::uint32_t>(p.x.size())};
  const std::vector<std::uint32_t> weights = {1, 5, 1024, 3, 77, 1, 2};
  std::vector<std::uint32_t> img(size * size);
  const Box box = splat(p, weights, size, img);
  std::vector<std::uint64_t> rows(size * size);
  std::vector<float> dens(size * size);
  convolve(img, size, box, radius, rows, dens);
  const std::vector<std::uint64_t> k = kernel_taps(radius);
  const Box r = read_region(box, size);
  for (int y = r.y0; y <= r.y1; ++y)
    for (int x = r.x0; x <= r.x1; ++x) {
      std::uint64_t direct = 0;
      for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx) {
          const int sx = x + dx, sy = y + dy;
          if (sx < 0 || sy < 0 || sx >= size || sy >= size) continue;
          direct += k[dx + radius] * k[dy + radius] * img[sy * size + sx];
        }
      ASSERT_EQ(dens[y * size + x], static_cast<float>(direct)) << x << "," << y;
    }
  // The box is the splatted pixels' box.
  int x0 = size, x1 = -1;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
      if (img[y * size + x]) x0 = std::min(x0, x), x1 = std::max(x1, x);
  EXPECT_EQ(box.x0, x0);
  EXPECT_EQ(box.x1, x1);
}

TEST(BundleSteps, SplatDropsPointsOutsideTheImage) {
  Points p = one_polyline({-0.5f, 0.0f, 31.99f, 32.0f, 5.5f}, {3, 3, 31.99f, 1, 7.25f});
  std::vector<std::uint32_t> img(32 * 32);
  const Box box = splat(p, {9}, 32, img);
  std::uint64_t total = 0;
  for (auto v : img) total += v;
  EXPECT_EQ(total, 27u);
  EXPECT_EQ(img[3 * 32 + 0], 9u);
  EXPECT_EQ(img[31 * 32 + 31], 9u);
  EXPECT_EQ(img[7 * 32 + 5], 9u);
  EXPECT_EQ(box.x0, 0);
  EXPECT_EQ(box.y0, 3);
  EXPECT_EQ(box.x1, 31);
  EXPECT_EQ(box.y1, 31);
}

TEST(BundleSteps, AdvectionMovesTowardThePeakByExactlyEpsHZ) {
  const int size = 128;
  // A peak of 50 points at (40.5, 60.5) and probes 6 px to its right and above it.
  Points p;
  for (int i = 0; i < 50; ++i)
    p.x.push_back(40.5f), p.y.push_back(60.5f), p.z.push_back(0), p.edge.push_back(0);
  const float probes[3][3] = {{46.5f, 60.5f, 1.0f}, {40.5f, 54.5f, 0.5f}, {44.0f, 57.0f, 0.25f}};
  for (const auto& q : probes)
    p.x.push_back(q[0]), p.y.push_back(q[1]), p.z.push_back(q[2]), p.edge.push_back(1);
  p.offsets = {0, 50, static_cast<std::uint32_t>(p.size())};
  std::vector<std::uint32_t> img(size * size);
  const Box box = splat(p, {10, 1}, size, img);
  std::vector<std::uint64_t> rows(size * size);
  std::vector<float> dens(size * size);
  convolve(img, size, box, 16, rows, dens);
  const Points before = p;
  const double step = 0.5 * 16;
  advect(p, dens, size, step);
  for (int i = 0; i < 50; ++i) EXPECT_EQ(p.x[i], 40.5f);  // z = 0: never moves
  for (int k = 0; k < 3; ++k) {
    const std::size_t i = 50 + k;
    const double dx = p.x[i] - before.x[i], dy = p.y[i] - before.y[i];
    EXPECT_NEAR(std::hypot(dx, dy), step * probes[k][2], 1e-5) << k;
    // Toward the peak: the move is along (peak − probe).
    const double tx = 40.5 - before.x[i], ty = 60.5 - before.y[i];
    EXPECT_GT((dx * tx + dy * ty) / (std::hypot(dx, dy) * std::hypot(tx, ty)), 0.99) << k;
  }
  // A point where the density is flat does not move.
  Points flat = one_polyline({100}, {100});
  advect(flat, dens, size, step);
  EXPECT_EQ(flat.x[0], 100.0f);
}

TEST(BundleSteps, SamplingIsBilinearBetweenTexelCentres) {
  std::vector<float> d(4 * 4, 0);
  d[1 * 4 + 1] = 100;
  d[1 * 4 + 2] = 200;
  EXPECT_DOUBLE_EQ(sample_density(d, 4, 1.5, 1.5), 100);  // texel (1, 1)'s centre
  EXPECT_DOUBLE_EQ(sample_density(d, 4, 2.0, 1.5), 150);  // halfway to (2, 1)
  EXPECT_DOUBLE_EQ(sample_density(d, 4, 2.0, 2.0), 75);
  EXPECT_DOUBLE_EQ(sample_density(d, 4, -3.0, 1.5), 0);  // clamped to column 0
}

TEST(BundleSteps, SmoothingIsTheHandComputedWeightedMean) {
  Points p = one_polyline({0, 10, 30, 60, 100}, {0, 5, 0, 5, 0}, {0, 1, 0.5f, 1, 0});
  const Points before = p;
  smooth(p, 1, 0.2, 1);
  EXPECT_EQ(p.x[0], 0.0f);  // z = 0
  EXPECT_EQ(p.x[4], 100.0f);
  // Point 1: mean of 0, 10, 30 = 40/3; x' = 0.8·10 + 0.2·40/3.
  EXPECT_FLOAT_EQ(p.x[1], static_cast<float>(0.8 * 10 + 0.2 * (40.0 / 3)));
  EXPECT_FLOAT_EQ(p.y[1], static_cast<float>(0.8 * 5 + 0.2 * (5.0 / 3)));
  // Point 2 with z = 0.5: λz = 0.1, mean of 10, 30, 60.
  EXPECT_FLOAT_EQ(p.x[2], static_cast<float>(0.9 * 30 + 0.1 * (100.0 / 3)));
  // The window stops at the polyline's ends: a window of 3 around point 1 holds points 0..4.
  Points q = before;
  smooth(q, 3, 1.0, 1);
  EXPECT_FLOAT_EQ(q.x[1], static_cast<float>((0 + 10 + 30 + 60 + 100) / 5.0));
  // Passes: two passes = the one-pass step twice.
  Points twice = before, once = before;
  smooth(twice, 1, 0.2, 2);
  smooth(once, 1, 0.2, 1);
  smooth(once, 1, 0.2, 1);
  EXPECT_EQ(twice.x, once.x);
}

TEST(BundleSteps, SmoothingStaysWithinEachPolyline) {
  Points p;
  p.x = {0, 10, 20, 1000, 1010};
  p.y = {0, 0, 0, 0, 0};
  p.z = {1, 1, 1, 1, 1};
  p.edge = {0, 0, 0, 1, 1};
  p.offsets = {0, 3, 5};
  smooth(p, 2, 1.0, 1);
  EXPECT_FLOAT_EQ(p.x[2], 10.0f);    // mean of 0, 10, 20 only
  EXPECT_FLOAT_EQ(p.x[3], 1005.0f);  // mean of 1000, 1010 only
}

}  // namespace
}  // namespace trailscope::bundling::detail
