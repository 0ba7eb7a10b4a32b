// One binary layer: exact distances on the medial axis, exact reconstruction from the full medial axis,
// simplification that only removes skeleton pixels as sigma grows. References are brute force.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "draw.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/dmd/dmd.hpp"
#include "trailscope/dmd/medial.hpp"

namespace trailscope::dmd {
namespace {

using test::blank;
using test::paint;

// Squared distance from (x, y) to the nearest outside pixel, the image's surroundings included.
std::int64_t brute_d2(const BinaryImage& b, int x, int y) {
  std::int64_t best =
      std::min<std::int64_t>({std::int64_t(x + 1) * (x + 1), std::int64_t(b.width - x) * (b.width - x),
                              std::int64_t(y + 1) * (y + 1), std::int64_t(b.height - y) * (b.height - y)});
  for (int v = 0; v < b.height; ++v)
    for (int u = 0; u < b.width; ++u)
      if (!b.at(u, v))
        best = std::min<std::int64_t>(best, std::int64_t(u - x) * (u - x) + std::int64_t(v - y) * (v - y));
  return best;
}

// Union of the open disks of an axis, pixel by pixel.
BinaryImage brute_inflate(const MedialAxis& a) {
  BinaryImage out = blank(a.width, a.height);
  for (int cy = 0; cy < a.height; ++cy)
    for (int cx = 0; cx < a.width; ++cx) {
      const std::int64_t r2 = a.squared_radius[static_cast<std::size_t>(cy) * a.width + cx];
      if (r2 <= 0) continue;
      for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x)
          if (std::int64_t(x - cx) * (x - cx) + std::int64_t(y - cy) * (y - cy) < r2)
            out.pixels[static_cast<std::size_t>(y) * a.width + x] = 1;
    }
  return out;
}

// A random blobby shape: disks, rectangles, a few holes and salt noise.
BinaryImage random_shape(std::mt19937& rng, int w, int h) {
  BinaryImage b = blank(w, h);
  std::uniform_real_distribution<double> ux(0, w), uy(0, h), ur(1.5, 12);
  for (int k = 0; k < 5; ++k) paint(b, std::uint8_t{1}, test::disk(ux(rng), uy(rng), ur(rng)));
  for (int k = 0; k < 3; ++k) {
    const int x0 = int(ux(rng)), y0 = int(uy(rng));
    paint(b, std::uint8_t{1}, test::rect(x0, y0, x0 + int(ur(rng)) * 2, y0 + int(ur(rng))));
  }
  for (int k = 0; k < 2; ++k) paint(b, std::uint8_t{0}, test::disk(ux(rng), uy(rng), ur(rng) / 3));
  for (int k = 0; k < 20; ++k) b.pixels[rng() % b.pixels.size()] ^= 1;
  return b;
}

TEST(MedialAxis, RadiiAreExactSquaredDistancesAndAxisIsInside) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    const BinaryImage b = random_shape(rng, 41 + trial, 33);
    const MedialAxis a = medial_axis(b);
    ASSERT_EQ(a.squared_radius.size(), b.pixels.size());
    for (int y = 0; y < b.height; ++y)
      for (int x = 0; x < b.width; ++x) {
        const std::int32_t r2 = a.squared_radius[static_cast<std::size_t>(y) * b.width + x];
        if (!b.at(x, y)) {
          EXPECT_EQ(r2, 0);
        } else if (r2 > 0) {
          EXPECT_EQ(r2, brute_d2(b, x, y)) << "at " << x << "," << y;
        }
      }
  }
}

TEST(MedialAxis, FullAxisReconstructsRandomShapesExactly) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 30; ++trial) {
    const BinaryImage b = random_shape(rng, 50, 40 + trial % 7);
    const MedialAxis a = medial_axis(b);
    const BinaryImage r = inflate(a);
    EXPECT_EQ(r.pixels, b.pixels) << "trial " << trial;
    EXPECT_EQ(r.pixels, brute_inflate(a).pixels) << "trial " << trial;
    EXPECT_LT(a.pixels(), std::count(b.pixels.begin(), b.pixels.end(), 1) + 1);
  }
}

TEST(MedialAxis, DiskAndRectangleComeBackExactlyThroughTheGreyPipeline) {
  for (const bool interpolate : {false, true}) {
    GreyImage g = test::blank_grey(96, 80);
    paint(g, std::uint8_t{255}, test::disk(30.3, 40.1, 21.7));
    paint(g, std::uint8_t{255}, test::rect(60, 10, 90, 35));
    DmdParams p;
    p.layers = 2;
    p.island = 0;
    p.saliency = 0;
    p.interpolate = interpolate;
    const DmdResult r = run_dmd(g, p);
    ASSERT_EQ(r.levels, (std::vector<int>{0, 255}));
    EXPECT_EQ(r.reconstruction.pixels, g.pixels) << "interpolate " << interpolate;
    EXPECT_TRUE(std::isinf(psnr(g, r.reconstruction)));
    // The axis of two convex shapes is a small part of them.
    EXPECT_LT(r.skeleton_pixels * 10, std::count(g.pixels.begin(), g.pixels.end(), 255));
  }
}

TEST(MedialAxis, NestedGreyShapesComeBackExactlyWithEnoughLayers) {
  GreyImage g = test::blank_grey(80, 64, 10);
  paint(g, std::uint8_t{90}, test::ellipse(40, 30, 30, 20));
  paint(g, std::uint8_t{170}, test::rect(20, 20, 45, 40));
  paint(g, std::uint8_t{250}, test::disk(55, 30, 6));
  DmdParams p;
  p.layers = 4;
  p.island = 0;
  p.saliency = 0;
  p.interpolate = false;
  const DmdResult r = run_dmd(g, p);
  EXPECT_EQ(r.levels, (std::vector<int>{10, 90, 170, 250}));
  EXPECT_EQ(r.reconstruction.pixels, g.pixels);
}

TEST(MedialAxis, SalienceOfADiskCentreIsAboutPiAndALoopIsInfinite) {
  BinaryImage b = blank(81, 81);
  paint(b, std::uint8_t{1}, test::disk(40, 40, 30));
  const MedialAxis a = medial_axis(b);
  EXPECT_GT(a.squared_radius[40 * 81 + 40], 0);
  EXPECT_NEAR(a.salience[40 * 81 + 40], M_PI, 0.35);  // half the perimeter over the radius

  BinaryImage ring = blank(81, 81);
  paint(ring, std::uint8_t{1}, test::disk(40, 40, 30));
  paint(ring, std::uint8_t{0}, test::disk(40, 40, 15));
  const MedialAxis ra = medial_axis(ring);
  const auto loops =
      std::count_if(ra.salience.begin(), ra.salience.end(), [](float s) { return std::isinf(s); });
  EXPECT_GT(loops, 2 * M_PI * 22 * 0.8);  // about the circle of radius 22.5 between the two borders
  // ... and a loop survives any simplification.
  EXPECT_EQ(simplify(ra, 100).pixels(), loops);
}

TEST(MedialAxis, SimplificationOnlyRemovesSkeletonPixelsAsSigmaGrows) {
  std::mt19937 rng(3);
  BinaryImage b = blank(120, 90);
  paint(b, std::uint8_t{1}, test::ellipse(60, 45, 50, 35));
  // boundary noise: bumps and dents of one or two pixels
  for (int k = 0; k < 60; ++k) {
    const double t = std::uniform_real_distribution<double>(0, 2 * M_PI)(rng);
    paint(b, std::uint8_t(k % 2), test::disk(60 + 50 * std::cos(t), 45 + 35 * std::sin(t), 1.5));
  }
  // Bumps painted over dents can enclose one-pixel holes, whose loops no simplification removes (they
  // are topology); the pipeline fills them as islands first, and so does this test.
  remove_islands(b, 10);
  const MedialAxis full = medial_axis(b);
  std::int64_t prev = full.pixels();
  std::vector<std::uint8_t> prev_mask(full.squared_radius.size());
  for (std::size_t i = 0; i < prev_mask.size(); ++i) prev_mask[i] = full.squared_radius[i] > 0;
  for (const double sigma : {0.1, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0}) {
    const MedialAxis s = simplify(full, sigma);
    const std::int64_t now = s.pixels();
    EXPECT_LE(now, prev) << "sigma " << sigma;
    for (std::size_t i = 0; i < prev_mask.size(); ++i) {
      if (s.squared_radius[i] > 0)
        EXPECT_TRUE(prev_mask[i]) << "pixel " << i << " came back at sigma " << sigma;
      prev_mask[i] = s.squared_radius[i] > 0;
    }
    // The simplified shape stays inside the original.
    const BinaryImage r = inflate(s);
    for (std::size_t i = 0; i < r.pixels.size(); ++i) ASSERT_LE(r.pixels[i], b.pixels[i]);
    prev = now;
  }
  const MedialAxis two = simplify(full, 2.0);
  EXPECT_LT(two.pixels() * 3, full.pixels()) << "noise branches should go at sigma 2";
  // ... but the main axis of the ellipse (its major axis, about y = 45 for 25 <= x <= 95) stays.
  int columns = 0;
  for (int x = 35; x <= 85; ++x) {
    bool on = false;
    for (int y = 42; y <= 48; ++y) on = on || two.squared_radius[static_cast<std::size_t>(y) * 120 + x] > 0;
    columns += on;
  }
  EXPECT_GE(columns, 45);
}

TEST(MedialAxis, SkeletonPixelsOfTheGreyPipelineFallWithSaliency) {
  GreyImage g = test::blank_grey(100, 80);
  std::mt19937 rng(9);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const double v = 200 * std::exp(-((x - 50.0) * (x - 50.0) + (y - 40.0) * (y - 40.0)) / 900.0) +
                       std::normal_distribution<double>(0, 6)(rng);
      g.pixels[static_cast<std::size_t>(y) * g.width + x] =
          static_cast<std::uint8_t>(std::clamp(v, 0.0, 255.0));
    }
  std::int64_t prev = std::numeric_limits<std::int64_t>::max();
  for (const double sigma : {0.0, 0.3, 0.6, 1.2, 2.4, 4.8}) {
    DmdParams p;
    p.saliency = sigma;
    const DmdResult r = run_dmd(g, p);
    EXPECT_LE(r.skeleton_pixels, prev) << "sigma " << sigma;
    EXPECT_EQ(r.medial_axis_pixels, run_dmd(g, DmdParams{}).medial_axis_pixels);
    prev = r.skeleton_pixels;
  }
}

TEST(MedialAxis, MalformedLayerAndSigmaAreRejected) {
  BinaryImage bad{4, 4, std::vector<std::uint8_t>(15, 0)};
  try {
    medial_axis(bad);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.param(), "layer");
  }
  const MedialAxis a = medial_axis(blank(4, 4));
  EXPECT_EQ(a.pixels(), 0);
  try {
    simplify(a, -1);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.param(), "saliency");
    EXPECT_EQ(std::string(e.what()), "saliency must be finite and >= 0 (got -1.000000)");
  }
}

}  // namespace
}  // namespace trailscope::dmd
