// The synthetic ToF camera: determinism, ground truth against the rendered depth, the sensor model (shot
// noise, ambient light, motion within the exposure, multipath), the cup interval, option validation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
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

// The speed of light in mm/s and the range per radian of phase at the sensor's modulation (4 pi f / c
// rad per mm of range: the light goes there and back).
constexpr double kLightMmPerS = 299'792'458e3;
double rad_per_mm(const ToFSensor& s) {
  return 4 * std::numbers::pi * s.modulation_hz / kLightMmPerS;
}

// A sensor without noise or holes: a huge well of electrons, no ambient light, no read noise.
ToFSensor ideal_sensor(ToFSensor s = {}) {
  s.electrons_per_unit = 1e9, s.full_well_e = 1e30, s.ambient_e = 0, s.read_noise_e = 0;
  s.dropout = 0, s.min_amplitude = 0, s.grazing_cos = 0;
  return s;
}

// The wall of the `plane` scenario faces the camera; the noise-free render of the same seed is the truth.
// Shot noise of a four-sample lock-in pixel (Lange & Seitz 2001; synth.hpp): each difference of two
// samples has variance B + read^2 (B the electrons per sample: signal / contrast + ambient), so the
// phase has sd sqrt((B + read^2) / 2) / A and the range L / (2 pi) times that (L = c / (2 f)); A = the
// amplitude in electrons, a0 * 0.8 * cos / (range / 1 m)^2 units of electrons_per_unit each; z's sd is the
// range's over |d| (d = the pixel's ray with z = 1). Measured on the central 24x24 px against the mean
// variance the model predicts there.
TEST(Synth, DepthNoiseFollowsShotNoiseOnAFlatWall) {
  const std::size_t n = 86;  // wall at 150 + 10 * i mm
  const ToFSynth noisy(options(Scenario::plane, n, 9)), exact(options(Scenario::plane, n, 9, true));
  const ToFSensor sensor = scenario_sensor(Scenario::plane);
  const Intrinsics& k = noisy.info().intrinsics;
  EXPECT_FALSE(noisy.info().has_truth);
  std::vector<double> measured;
  for (std::size_t f : {15u, 45u, 75u}) {  // 300, 600, 900 mm
    const DepthFrame a = noisy.render(f), b = exact.render(f);
    EXPECT_FALSE(a.truth);
    const double z = 150.0 + 10.0 * f;
    double sum = 0, sum2 = 0, model2 = 0;
    int count = 0;
    for (int v = k.height / 2 - 12; v < k.height / 2 + 12; ++v)
      for (int u = k.width / 2 - 12; u < k.width / 2 + 12; ++u) {
        const std::size_t i = static_cast<std::size_t>(v) * k.width + u;
        EXPECT_NEAR(b.depth_mm[i], z, 1e-3);      // the noise-free wall is exact
        if (std::isnan(a.depth_mm[i])) continue;  // dropouts
        const double r = a.depth_mm[i] - b.depth_mm[i];
        sum += r, sum2 += r * r, ++count;
        const double dn = std::hypot((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0), range = z * dn;
        const double amp = sensor.electrons_per_unit * sensor.a0 * 1e6 * 0.8 / dn / (range * range);
        const double electrons =
            amp / sensor.demod_contrast + sensor.ambient_e + sensor.read_noise_e * sensor.read_noise_e;
        const double sd_z = std::sqrt(electrons / 2) / amp / rad_per_mm(sensor) / dn;
        model2 += sd_z * sd_z;
      }
    EXPECT_GT(count, 540);  // of 576: dropouts are 0.3%
    const double mean = sum / count, sd = std::sqrt(sum2 / count - mean * mean),
                 model = std::sqrt(model2 / count);
    // The wall moves 10 mm a frame: the two sample pairs, half an exposure apart, see it 0.125 mm apart,
    // a bias far below this bound (DepthOfAMovingWallIsTheTwoInstantsPhase has the exact one).
    EXPECT_NEAR(mean, 0.0, 4 * model / std::sqrt(count));
    EXPECT_NEAR(sd, model, 0.12 * model) << "z = " << z;
    measured.push_back(sd);
  }
  EXPECT_LT(measured[0], measured[1]);
  EXPECT_LT(measured[1], measured[2]);
}

// More ambient light, more noise: at 900 mm with sunlight's 1,200,000 e- per sample (the noisy scenario's
// ambient) the wall's depth noise is several times the indoor one.
TEST(Synth, AmbientLightAddsNoise) {
  SynthOptions o = options(Scenario::plane, 86, 9);
  const DepthFrame exact = ToFSynth(options(Scenario::plane, 86, 9, true)).render(75);
  const auto sd_of = [&](double ambient) {
    ToFSensor s = scenario_sensor(Scenario::plane);
    s.ambient_e = ambient, s.dropout = 0;
    o.sensor = s;
    const DepthFrame a = ToFSynth(o).render(75);
    double sum2 = 0;
    int count = 0;
    for (std::size_t i = 0; i < a.depth_mm.size(); ++i)
      if (!std::isnan(a.depth_mm[i])) sum2 += std::pow(a.depth_mm[i] - exact.depth_mm[i], 2), ++count;
    return std::sqrt(sum2 / count);
  };
  const double indoor = sd_of(scenario_sensor(Scenario::standard).ambient_e);
  const double sunlit = sd_of(scenario_sensor(Scenario::noisy).ambient_e);
  EXPECT_GT(sunlit, 2.5 * indoor) << indoor << " " << sunlit;
}

// Motion within the exposure (synth.hpp): the pixel's sample pairs 0/180 and 90/270 deg are taken a
// quarter of the exposure before and after the timestamp. A wall moving 10 mm a frame, with an exposure of
// a whole frame, is 2.5 mm nearer at the first pair and 2.5 mm farther at the second; the measured phase
// is atan2(A2 sin p2, A1 cos p1) of the two returns (amplitude A ~ cos / range^2, phase p = k * range).
// Computed here from that alone and compared pixel by pixel (no noise).
TEST(Synth, DepthOfAMovingWallIsTheTwoInstantsPhase) {
  SynthOptions o = options(Scenario::plane, 86, 9);
  ToFSensor s = ideal_sensor();
  s.exposure_s = 1.0 / o.fps;
  o.sensor = s;
  const ToFSynth synth(o);
  const Intrinsics& k = synth.info().intrinsics;
  const double kp = rad_per_mm(s);
  for (std::size_t f : {15u, 45u}) {
    const DepthFrame a = synth.render(f);
    const double z = 150.0 + 10.0 * f, z1 = z - 2.5, z2 = z + 2.5;
    double worst = 0, bias = 0;
    for (int v = 0; v < k.height; v += 7)
      for (int u = 0; u < k.width; u += 5) {
        const double dn = std::hypot((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
        const double r1 = z1 * dn, r2 = z2 * dn, a1 = 1 / (r1 * r1), a2 = 1 / (r2 * r2);
        const double expected = std::atan2(a2 * std::sin(kp * r2), a1 * std::cos(kp * r1)) / kp / dn;
        const float got = a.depth_mm[static_cast<std::size_t>(v) * k.width + u];
        ASSERT_FALSE(std::isnan(got));
        worst = std::max(worst, std::abs(got - expected));
        bias = std::max(bias, std::abs(expected - z));
      }
    EXPECT_LT(worst, 0.01) << "frame " << f;
    EXPECT_GT(bias, 0.5) << "frame " << f;  // the artefact is there, not the mean depth
  }
}

// Multipath (synth.hpp): light that reaches a surface by way of another arrives later, so depth reads too
// far wherever surfaces face each other, never too near; a flat wall has none; twice the indirect light,
// about twice the bias (the indirect return is small beside the direct one).
TEST(Synth, MultipathPushesConcaveRegionsAwayAndSparesAFlatWall) {
  const auto render = [](Scenario sc, double multipath, std::size_t f) {
    SynthOptions o = options(sc, 60, 4);
    ToFSensor s = ideal_sensor();
    s.exposure_s = 0, s.multipath = multipath;
    o.sensor = s;
    return ToFSynth(o).render(f);
  };
  const DepthFrame wall0 = render(Scenario::plane, 0, 30), wall1 = render(Scenario::plane, 1, 30);
  for (std::size_t i = 0; i < wall0.depth_mm.size(); ++i) ASSERT_EQ(wall0.depth_mm[i], wall1.depth_mm[i]);

  const DepthFrame none = render(Scenario::standard, 0, 40), one = render(Scenario::standard, 1, 40),
                   two = render(Scenario::standard, 2, 40);
  // Pixels off depth edges (mixed pixels blend two surfaces, whose indirect light the sum shifts either way).
  const int W = SynthOptions{}.width, H = SynthOptions{}.height;
  const auto smooth = [&](int u, int v) {
    const float z = none.depth_mm[static_cast<std::size_t>(v) * W + u];
    if (std::isnan(z) || z > 900) return false;
    for (const auto& [du, dv] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
      const float o = none.depth_mm[static_cast<std::size_t>(v + dv) * W + u + du];
      if (std::isnan(o) || std::abs(o - z) > ToFSensor{}.edge_mm) return false;
    }
    return true;
  };
  std::vector<double> d1;
  double sum1 = 0, sum2 = 0, lowest = 0;
  for (int v = 1; v + 1 < H; ++v)
    for (int u = 1; u + 1 < W; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * W + u;
      if (!smooth(u, v)) continue;
      const double b1 = one.depth_mm[i] - none.depth_mm[i], b2 = two.depth_mm[i] - none.depth_mm[i];
      lowest = std::min(lowest, b1);
      d1.push_back(b1);
      sum1 += b1, sum2 += b2;
    }
  ASSERT_GT(d1.size(), 5000u);
  std::sort(d1.begin(), d1.end());
  EXPECT_GT(lowest, -0.05);  // never nearer (beyond the little noise left)
  // Seed 4, frame 40: median 0.09 mm, 90th percentile 1.3 mm, 99th 16 mm, at most 42 mm, the largest
  // where the belly meets the udder at grazing incidence, whose weak direct return (a tenth of a teat's)
  // the light from the facing surface outweighs most.
  EXPECT_GT(d1[d1.size() * 9 / 10], 0.5);
  EXPECT_LT(d1[d1.size() * 99 / 100], 25.0);
  EXPECT_LT(d1.back(), 60.0);
  EXPECT_GT(sum2 / sum1, 1.6);
  EXPECT_LT(sum2 / sum1, 2.2);
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
  o = {};
  o.sensor = ToFSensor{};
  o.sensor->dropout = 2;
  test::expect_error([&] { ToFSynth s(o); }, Error::Kind::invalid_argument, "sensor.dropout",
                     "sensor.dropout must be in [0, 1]");
  o.sensor = ToFSensor{};
  o.sensor->exposure_s = 0.05;  // longer than a frame at 25 fps
  test::expect_error([&] { ToFSynth s(o); }, Error::Kind::invalid_argument, "sensor.exposure_s",
                     "sensor.exposure_s must be in [0, 1 / fps]");
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
