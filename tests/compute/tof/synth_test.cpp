// The synthetic ToF camera: determinism, ground truth against the rendered depth, the noise model on a
// flat wall, the cup interval, option validation.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "test_support.hpp"
#include "tof_test_util.hpp"
#include "trailscope/tof/depth_video_io.hpp"
#include "trailscope/tof/synth.hpp"

namespace trailscope::tof {
namespace {
namespace fs = std::filesystem;

SynthOptions options(Scenario s, std::size_t frames, std::uint64_t seed, bool noise_free = false) {
  SynthOptions o;
  o.scenario = s;
  o.frames = frames;
  o.seed = seed;
  o.noise_free = noise_free;
  return o;
}

TEST(Synth, SameSeedSameBytesInAnyOrder) {
  const ToFSynth a(options(Scenario::occluded, 40, 11)), b(options(Scenario::occluded, 40, 11));
  for (std::size_t f : {39u, 3u, 17u}) {  // out of order: a frame depends on its index only
    const DepthFrame x = a.render(f), y = b.render(f);
    EXPECT_TRUE(test::same_bits(x.depth_mm, y.depth_mm)) << f;
    EXPECT_TRUE(test::same_bits(x.amplitude, y.amplitude)) << f;
    EXPECT_EQ(x.truth, y.truth) << f;
  }
  const ToFSynth c(options(Scenario::occluded, 40, 12));
  EXPECT_FALSE(test::same_bits(a.render(3).depth_mm, c.render(3).depth_mm));
  // And on disk: two writes of the same seed give identical files.
  test::TempDir dir;
  for (const char* name : {"a", "b"})
    write_depth_video(synthesize(options(Scenario::noisy, 5, 4)), dir.path() / name);
  for (const char* f : {"manifest.json", "depth/000004.png", "amplitude/000004.png"})
    EXPECT_EQ(test::slurp(dir.path() / "a" / f), test::slurp(dir.path() / "b" / f)) << f;
}

TEST(Synth, TeatShapesAreInTheDocumentedRanges) {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const ToFSynth s(options(Scenario::standard, 1, seed));
    for (const TeatShape& t : s.teat_shapes()) {
      EXPECT_GE(t.length_mm, 30);
      EXPECT_LE(t.length_mm, 70);
      EXPECT_GE(t.diameter_mm, 18);
      EXPECT_LE(t.diameter_mm, 30);
      EXPECT_GE(t.tilt_deg, 5);
      EXPECT_LE(t.tilt_deg, 25);
    }
  }
}

// For every visible tip: its projection, computed here from the intrinsics, matches tip_px; the pixel it
// falls in shows depth within the pixel-footprint tolerance of the tip's z (noise-free render); the box
// holds that pixel. The tip is the apex of a hemisphere of radius >= 9 mm: half a pixel off the apex
// (footprint z / fx / 2 mm), the surface recedes by at most a few mm at the tilts drawn.
TEST(Synth, VisibleTipsAreWhereTheDepthSaysTheyAre) {
  for (Scenario sc : {Scenario::standard, Scenario::fast_motion, Scenario::occluded}) {
    const ToFSynth s(options(sc, 400, 5, true));
    const Intrinsics& k = s.info().intrinsics;
    int checked = 0;
    double worst = 0;
    for (std::size_t f = 0; f < 400; f += 3) {
      const DepthFrame fr = s.render(f);
      ASSERT_TRUE(fr.truth);
      for (int t = 0; t < kTeatCount; ++t) {
        const TeatTruth& tt = fr.truth->teats[t];
        if (!tt.visible) continue;
        const double u = k.fx * tt.tip_mm[0] / tt.tip_mm[2] + k.cx,
                     v = k.fy * tt.tip_mm[1] / tt.tip_mm[2] + k.cy;
        ASSERT_TRUE(tt.tip_px);
        EXPECT_NEAR((*tt.tip_px)[0], u, 1e-9);
        EXPECT_NEAR((*tt.tip_px)[1], v, 1e-9);
        const long iu = std::lround(u), iv = std::lround(v);
        ASSERT_TRUE(iu >= 0 && iu < k.width && iv >= 0 && iv < k.height);
        const float z = fr.depth_mm[iv * k.width + iu];
        const double footprint = tt.tip_mm[2] / k.fx;  // mm per pixel at the tip
        ASSERT_FALSE(std::isnan(z));
        EXPECT_NEAR(z, tt.tip_mm[2], 1.0 + 2.0 * footprint)
            << to_string(sc) << " frame " << f << " teat " << t;
        worst = std::max(worst, std::abs(z - tt.tip_mm[2]) / footprint);
        ASSERT_TRUE(tt.box_px);
        EXPECT_LE(tt.box_px->x, iu);
        EXPECT_GE(tt.box_px->x + tt.box_px->w, iu);
        EXPECT_LE(tt.box_px->y, iv);
        EXPECT_GE(tt.box_px->y + tt.box_px->h, iv);
        EXPECT_GT(tt.visible_fraction, 0);
        ++checked;
      }
    }
    EXPECT_GT(checked, 300) << to_string(sc);
    RecordProperty(std::string(to_string(sc)) + "_worst_depth_error_px", std::to_string(worst));
  }
}

// The wall of the `plane` scenario faces the camera; the noise-free render of the same seed is the truth.
// sigma = floor + gain * sqrt(1000 / amplitude), amplitude = 1000 * 0.8 * cos / (range / 1 m)^2 (synth.hpp):
// on the optical axis 0.5 + 4 * (z / 1000) / sqrt(0.8) mm. Measured on the central 24x24 px.
TEST(Synth, DepthNoiseGrowsWithDistanceOnAFlatWall) {
  const std::size_t n = 86;  // wall at 150 + 10 * i mm
  const ToFSynth noisy(options(Scenario::plane, n, 9)), exact(options(Scenario::plane, n, 9, true));
  const Intrinsics& k = noisy.info().intrinsics;
  EXPECT_FALSE(noisy.info().has_truth);
  std::vector<double> measured;
  for (std::size_t f : {15u, 45u, 75u}) {  // 300, 600, 900 mm
    const DepthFrame a = noisy.render(f), b = exact.render(f);
    EXPECT_FALSE(a.truth);
    double sum = 0, sum2 = 0;
    int count = 0;
    for (int v = k.height / 2 - 12; v < k.height / 2 + 12; ++v)
      for (int u = k.width / 2 - 12; u < k.width / 2 + 12; ++u) {
        const std::size_t i = static_cast<std::size_t>(v) * k.width + u;
        EXPECT_NEAR(b.depth_mm[i], 150.0 + 10.0 * f, 1e-3);  // the noise-free wall is exact
        if (std::isnan(a.depth_mm[i])) continue;             // dropouts
        const double r = a.depth_mm[i] - b.depth_mm[i];
        sum += r, sum2 += r * r, ++count;
      }
    EXPECT_GT(count, 540);  // of 576: dropouts are 0.3%
    const double mean = sum / count, sd = std::sqrt(sum2 / count - mean * mean);
    const double z = 150.0 + 10.0 * f, model = 0.5 + 4.0 * (z / 1000.0) / std::sqrt(0.8);
    EXPECT_NEAR(mean, 0.0, 4 * model / std::sqrt(count));
    EXPECT_NEAR(sd, model, 0.12 * model) << "z = " << z;
    measured.push_back(sd);
  }
  EXPECT_LT(measured[0], measured[1]);
  EXPECT_LT(measured[1], measured[2]);
}

TEST(Synth, CupsHideTheTeatsInTheirIntervalAndComeOff) {
  const std::size_t n = 250;
  const ToFSynth s(options(Scenario::cups_attached, n, 2, true));
  const auto& cups = s.cup_intervals();
  std::size_t last_end = 0;
  for (int t = 0; t < kTeatCount; ++t) {
    ASSERT_FALSE(cups[t].empty());
    last_end = std::max(last_end, cups[t].end);
  }
  // Sliding off takes about 0.4 s; from then on every teat must be visible again.
  const std::size_t free_from = last_end + static_cast<std::size_t>(std::ceil(0.4 * 25)) + 1;
  ASSERT_LT(free_from + 20, n);
  for (std::size_t f = 0; f < n; ++f) {
    const DepthFrame fr = s.render(f);
    for (int t = 0; t < kTeatCount; ++t) {
      const TeatTruth& tt = fr.truth->teats[t];
      if (cups[t].contains(f)) {
        EXPECT_FALSE(tt.visible) << "frame " << f << " teat " << t;
        EXPECT_TRUE(tt.cup_attached) << "frame " << f << " teat " << t;
      } else {
        EXPECT_FALSE(tt.cup_attached) << "frame " << f << " teat " << t;
      }
      if (f >= free_from) {
        EXPECT_TRUE(tt.visible) << "frame " << f << " teat " << t;
      }
    }
  }
  // Other scenarios attach none, except `occluded`, which puts one cup on one teat.
  // (Named, not temporaries: a range-for over a temporary's member would read a destroyed synth.)
  const ToFSynth standard(options(Scenario::standard, 100, 1)), occluded(options(Scenario::occluded, 100, 1));
  for (const FrameInterval& c : standard.cup_intervals()) EXPECT_TRUE(c.empty());
  int with_cup = 0;
  for (const FrameInterval& c : occluded.cup_intervals()) with_cup += !c.empty();
  EXPECT_EQ(with_cup, 1);
}

TEST(Synth, SensorEffectsAppear) {
  // Noisy frames have holes (dropouts, grazing, out of range) and flying pixels: depths between the
  // two sides of an edge, which the noise-free render never has at that pixel.
  const ToFSynth noisy(options(Scenario::standard, 10, 8)), exact(options(Scenario::standard, 10, 8, true));
  const DepthFrame a = noisy.render(0), b = exact.render(0);
  std::size_t holes = 0, far_off = 0;
  for (std::size_t i = 0; i < a.depth_mm.size(); ++i) {
    if (std::isnan(a.depth_mm[i])) {
      holes += !std::isnan(b.depth_mm[i]);
      continue;
    }
    if (!std::isnan(b.depth_mm[i]) && std::abs(a.depth_mm[i] - b.depth_mm[i]) > 40) ++far_off;
  }
  EXPECT_GT(holes, 0.002 * a.depth_mm.size());
  EXPECT_GT(far_off, 20u);  // flying pixels (noise alone is ~2-5 mm)
}

TEST(Synth, OptionsAreValidated) {
  SynthOptions o;
  o.width = 4;
  test::expect_error([&] { ToFSynth s(o); }, Error::Kind::invalid_argument, "width",
                     "width must be 8..1024 px, not 4");
  o = {};
  o.frames = 0;
  test::expect_error([&] { ToFSynth s(o); }, Error::Kind::invalid_argument, "frames", "frames must be >= 1");
  o = {};
  o.scenario = Scenario::cups_attached;
  o.frames = 19;
  test::expect_error([&] { ToFSynth s(o); }, Error::Kind::invalid_argument, "frames",
                     "the cups-attached scenario needs at least 20 frames");
  test::expect_error(
      [] { parse_scenario("rainy"); }, Error::Kind::invalid_argument, "scenario",
      "scenario must be one of standard, noisy, occluded, cups-attached, fast-motion, plane, not 'rainy'");
  EXPECT_EQ(parse_scenario("cups-attached"), Scenario::cups_attached);
  // Any size renders; intrinsics keep the field of view.
  o = {};
  o.width = 320;
  o.height = 240;
  o.frames = 2;
  const ToFSynth big(o);
  EXPECT_DOUBLE_EQ(big.info().intrinsics.fx, 150.0 * 320 / 176);
  EXPECT_EQ(big.render(1).depth_mm.size(), 320u * 240u);
}

}  // namespace
}  // namespace trailscope::tof
