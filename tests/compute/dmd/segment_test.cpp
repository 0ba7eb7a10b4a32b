// Segmentation: four teat-like capsules hanging below an ellipse (a near = bright depth-like image)
// come out as four peak segments, one per capsule.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "draw.hpp"
#include "trailscope/dmd/dmd.hpp"

namespace trailscope::dmd {
namespace {

struct Udder {
  GreyImage image;
  std::vector<BinaryImage> teats;  // one mask per capsule
  std::vector<std::pair<int, int>> tips;
};

// An ellipse "udder" that is a gentle dome (grey 90-130) and four vertical capsules below it whose
// grey rises towards the tip (150 -> 220), as a camera looking up at them would see nearness, plus
// Gaussian noise.
Udder draw_udder(int w, int h, double noise, unsigned seed) {
  Udder u;
  u.image = test::blank_grey(w, h, 0);
  const double cx = w / 2.0, cy = h * 0.3, rx = w * 0.38, ry = h * 0.2;
  std::vector<double> value(static_cast<std::size_t>(w) * h, 0);
  const auto dome = test::ellipse(cx, cy, rx, ry);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (dome(x, y)) {
        const double a = (x - cx) / rx, b = (y - cy) / ry;
        value[static_cast<std::size_t>(y) * w + x] = 90 + 40 * std::sqrt(std::max(0.0, 1 - a * a - b * b));
      }
  const double top = cy + ry * 0.6, tip = cy + ry + h * 0.25, r = w * 0.03;
  for (int k = 0; k < 4; ++k) {
    const double tx = cx + (k - 1.5) * rx * 0.5;
    const auto cap = test::capsule(tx, top, tip, r);
    BinaryImage mask = test::blank(w, h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        if (cap(x, y)) {
          const double t = std::clamp((y - top) / (tip - top), 0.0, 1.0);
          value[static_cast<std::size_t>(y) * w + x] = 150 + 70 * t;
          mask.pixels[static_cast<std::size_t>(y) * w + x] = 1;
        }
    u.teats.push_back(mask);
    u.tips.emplace_back(static_cast<int>(std::lround(tx)), static_cast<int>(std::lround(tip + r * 0.5)));
  }
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0, noise);
  for (std::size_t i = 0; i < value.size(); ++i)
    u.image.pixels[i] =
        static_cast<std::uint8_t>(std::clamp(std::lround(value[i] + (value[i] > 0 ? n(rng) : 0)), 0L, 255L));
  return u;
}

double iou(const std::vector<std::int32_t>& labels, int label, const BinaryImage& mask) {
  std::int64_t both = 0, either = 0;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    const bool a = labels[i] == label, b = mask.pixels[i] != 0;
    both += a && b;
    either += a || b;
  }
  return either ? double(both) / double(either) : 0;
}

void expect_four_teats(const Udder& u, const DmdResult& r) {
  ASSERT_EQ(r.labels.size(), u.image.pixels.size());
  std::set<int> seen;
  for (std::size_t k = 0; k < u.teats.size(); ++k) {
    const int label = r.labels[static_cast<std::size_t>(u.tips[k].second) * u.image.width + u.tips[k].first];
    ASSERT_GE(label, 1);
    const Segment& s = r.segments[label - 1];
    EXPECT_EQ(s.kind, SegmentKind::peak) << "teat " << k;
    EXPECT_GT(iou(r.labels, label, u.teats[k]), 0.6) << "teat " << k;
    EXPECT_TRUE(seen.insert(label).second) << "teats " << k << " share a segment";
    // the statistics describe the segment's pixels
    std::int64_t area = 0;
    double sx = 0;
    for (std::size_t i = 0; i < r.labels.size(); ++i)
      if (r.labels[i] == label) {
        ++area;
        sx += double(i % u.image.width);
      }
    EXPECT_EQ(s.area, area);
    EXPECT_NEAR(s.cx, sx / double(area), 1e-9);
    EXPECT_NEAR(s.cx, u.tips[k].first, 2.0);
    EXPECT_GT(s.mean_value, 150);
  }
  const auto peaks = std::count_if(r.segments.begin(), r.segments.end(),
                                   [](const Segment& s) { return s.kind == SegmentKind::peak; });
  EXPECT_GE(peaks, 4);
  EXPECT_LE(peaks, 5);  // the four teats and at most the dome's own summit
}

TEST(Segmentation, FourCapsulesBelowAnEllipseAreFourPeaks) {
  const Udder u = draw_udder(176, 144, 0, 1);
  const DmdResult r = run_dmd(u.image, DmdParams{});
  expect_four_teats(u, r);
  EXPECT_EQ(r.segments[0].kind, SegmentKind::canvas);  // the top-left pixel is background
  std::printf("clean: %zu segments, %zu layers, %.2f ms\n", r.segments.size(), r.levels.size(),
              r.times.total_ms);
}

TEST(Segmentation, SurvivesNoiseThanksToIslandsAndSimplification) {
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const Udder u = draw_udder(176, 144, 4.0, seed);
    DmdParams p;
    p.layers = 16;
    p.island = 0.004;
    const DmdResult r = run_dmd(u.image, p);
    expect_four_teats(u, r);
    std::printf(
        "noisy seed %u: %zu segments, %.2f ms (skeleton %.2f, simplify %.2f, reconstruct %.2f, "
        "stack %.2f, segment %.2f)\n",
        seed, r.segments.size(), r.times.total_ms, r.times.skeleton_ms, r.times.simplify_ms,
        r.times.reconstruct_ms, r.times.stack_ms, r.times.segment_ms);
  }
}

}  // namespace
}  // namespace trailscope::dmd
