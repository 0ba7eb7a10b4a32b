// Event detection on a constructed signal whose fixations, saccades and signal loss are known by
// construction, and Cohen's kappa against a computation by hand.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "trailscope/core/error.hpp"
#include "trailscope/gaze/events.hpp"

namespace trailscope::gaze {
namespace {

using ET = EventType;

/// A 500 Hz recording in degrees: fixation at (0, 0) for 200 ms, a 40 ms saccade to (10, 0), fixation
/// 200 ms, a 30 ms saccade to (10, 5), fixation 200 ms; a small deterministic tremor (±0.01 deg) on top.
/// `truth` gets the label of each sample; ramps' samples strictly between the two fixations are saccade.
Recording constructed(std::vector<ET>& truth, bool with_loss = false) {
  Recording r;
  r.units = Units::deg;
  const double dt = 2;
  double t = 1000;
  const auto add = [&](double x, double y, ET label) {
    const std::size_t i = r.size();
    r.t_ms.push_back(t);
    r.x.push_back(x + 0.01 * std::sin(double(i) * 1.7));
    r.y.push_back(y + 0.01 * std::cos(double(i) * 2.3));
    r.valid.push_back(1);
    truth.push_back(label);
    t += dt;
  };
  const auto fix = [&](double x, double y) {
    for (int k = 0; k < 100; ++k) add(x, y, ET::fixation);
  };
  const auto sacc = [&](double x0, double y0, double x1, double y1, int samples) {
    for (int k = 1; k < samples; ++k) {
      const double a = double(k) / samples;
      add(x0 + a * (x1 - x0), y0 + a * (y1 - y0), ET::saccade);
    }
  };
  fix(0, 0);
  sacc(0, 0, 10, 0, 20);
  fix(10, 0);
  sacc(10, 0, 10, 5, 15);
  fix(10, 5);
  if (with_loss) {
    // 20 samples of signal loss late in the second fixation (samples 119..218).
    for (std::size_t i = 190; i < 210; ++i) {
      r.valid[i] = 0, r.x[i] = r.y[i] = std::nan("");
      truth[i] = ET::blink;
    }
  }
  return r;
}

struct Run {
  ET type;
  std::size_t first, last;
};
std::vector<Run> runs(const std::vector<ET>& l) {
  std::vector<Run> out;
  for (std::size_t i = 0; i < l.size();) {
    std::size_t j = i;
    while (j + 1 < l.size() && l[j + 1] == l[i]) ++j;
    out.push_back({l[i], i, j});
    i = j + 1;
  }
  return out;
}

/// The detector's runs match the truth's run for run (same types in order; none runs of at most
/// `tol` samples at boundaries ignored), with boundaries at most `tol` samples apart.
void expect_runs(const std::vector<ET>& got, const std::vector<ET>& truth, std::size_t tol) {
  std::vector<Run> g;
  for (const Run& r : runs(got))
    if (!(r.type == ET::none && r.last - r.first < tol)) g.push_back(r);
  const std::vector<Run> w = runs(truth);
  ASSERT_EQ(g.size(), w.size());
  for (std::size_t k = 0; k < w.size(); ++k) {
    SCOPED_TRACE("run " + std::to_string(k));
    EXPECT_EQ(g[k].type, w[k].type);
    EXPECT_LE(std::max(g[k].first, w[k].first) - std::min(g[k].first, w[k].first), tol);
    EXPECT_LE(std::max(g[k].last, w[k].last) - std::min(g[k].last, w[k].last), tol);
  }
}

TEST(GazeEvents, IvtFindsTheConstructedEvents) {
  std::vector<ET> truth;
  const Recording r = constructed(truth);
  EventParams p;
  p.method = Method::ivt;
  const Detection d = detect_events(r, p);
  ASSERT_EQ(d.labels.size(), r.size());
  // The central difference reaches into the ramp from the samples on either side: 1 sample.
  expect_runs(d.labels, truth, 1);
  ASSERT_EQ(d.events.size(), 5u);
  EXPECT_EQ(d.events[1].type, ET::saccade);
  EXPECT_NEAR(d.events[1].t_start_ms, 1000 + 100 * 2, 2.0 + 1e-9);
}

TEST(GazeEvents, IdtFindsTheConstructedEvents) {
  std::vector<ET> truth;
  const Recording r = constructed(truth);
  EventParams p;
  p.method = Method::idt;
  // A 0.5 deg step per ramp sample: a fixation may take up to 2 ramp samples before its dispersion passes
  // 1 deg, on both sides.
  expect_runs(detect_events(r, p).labels, truth, 2);
}

TEST(GazeEvents, AdaptiveFindsTheConstructedEvents) {
  std::vector<ET> truth;
  const Recording r = constructed(truth);
  EventParams p;
  p.method = Method::adaptive;
  const Detection d = detect_events(r, p);
  // The 20 ms Savitzky-Golay window spreads a saccade's velocity by its half-width (5 samples); the onset
  // and offset then walk on to the next local velocity minimum of the tremor (up to 2 more).
  expect_runs(d.labels, truth, 7);
  // Tremor only below the peak threshold: it converged far below the saccades' 250 deg/s.
  EXPECT_GT(d.peak_threshold_deg_s, d.onset_threshold_deg_s);
  EXPECT_LT(d.peak_threshold_deg_s, 50);
}

TEST(GazeEvents, InvalidSamplesAreBlinksInEveryMethod) {
  for (Method m : {Method::ivt, Method::idt, Method::adaptive}) {
    SCOPED_TRACE(to_string(m));
    std::vector<ET> truth;
    const Recording r = constructed(truth, true);
    EventParams p;
    p.method = m;
    const Detection d = detect_events(r, p);
    for (std::size_t i = 190; i < 210; ++i) EXPECT_EQ(d.labels[i], ET::blink) << i;
    // The fixation before the loss and the next one are still fixations.
    EXPECT_EQ(d.labels[150], ET::fixation);
    EXPECT_EQ(d.labels[280], ET::fixation);
  }
}

TEST(GazeEvents, AdaptiveTreatsGlitchesAsNoise) {
  // One sample 50 deg off in the first fixation: no eye moves there and back in 4 ms. The speeds around it
  // (Savitzky-Golay, 11 samples) exceed 1000 deg/s or change by more than 100,000 deg/s^2, so they are
  // noise (blink), not a saccade; I-VT, with no such rule, calls the glitch a saccade.
  std::vector<ET> truth;
  Recording r = constructed(truth);
  r.x[50] += 50;
  EventParams p;
  p.method = Method::adaptive;
  const Detection d = detect_events(r, p);
  for (std::size_t i = 40; i <= 60; ++i) EXPECT_NE(d.labels[i], ET::saccade) << i;
  EXPECT_EQ(d.labels[45], ET::blink);
  EXPECT_EQ(d.labels[55], ET::blink);
  EXPECT_EQ(detect_events(r, EventParams{}).labels[49], ET::saccade);
}

TEST(GazeEvents, DamagedClocks) {
  // Times that go back are refused with the sample that does it (0-based; t = 1000 + 2k ms, so sample 10
  // moved to sample 8's 1016 ms comes after sample 9's 1018 ms).
  std::vector<ET> truth;
  Recording r = constructed(truth);
  r.t_ms[10] = r.t_ms[8];
  try {
    detect_events(r, EventParams{});
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::unprocessable);
    EXPECT_STREQ(e.what(),
                 "sample times must be finite and must not decrease; sample 10 is at 1016 ms after 1018 ms");
  }
  // A clock that stands still: no I-DT window ever lasts 100 ms, so every sample is a saccade (and the
  // window search does not rescan the recording for each sample).
  Recording still;
  still.units = Units::deg;
  const std::size_t n = 300'000;
  still.t_ms.assign(n, 5.0), still.x.assign(n, 1.0), still.y.assign(n, 1.0), still.valid.assign(n, 1);
  EventParams p;
  p.method = Method::idt;
  const Detection d = detect_events(still, p);
  EXPECT_EQ(std::count(d.labels.begin(), d.labels.end(), ET::saccade), std::ptrdiff_t(n));
}

TEST(GazeEvents, MinimumFixationDurationDropsShortRuns) {
  std::vector<ET> truth;
  Recording r = constructed(truth);
  EventParams p;
  p.ivt.min_fixation_ms = 250;  // every constructed fixation lasts 200 ms
  const Detection d = detect_events(r, p);
  for (ET l : d.labels) EXPECT_NE(l, ET::fixation);
}

TEST(GazeEvents, PointVelocityByHand) {
  // Three samples 10 ms apart at x = 0, 1, 3 deg: centre (3 - 0) / 0.02 s = 150 deg/s; ends one-sided:
  // 1 / 0.01 = 100 and 2 / 0.01 = 200.
  const auto v = point_velocity({0, 10, 20}, {0, 1, 3}, {0, 0, 0}, {1, 1, 1});
  EXPECT_DOUBLE_EQ(v[0], 100);
  EXPECT_DOUBLE_EQ(v[1], 150);
  EXPECT_DOUBLE_EQ(v[2], 200);
  const auto w = point_velocity({0, 10, 20}, {0, 1, 3}, {0, 0, 0}, {1, 0, 1});
  EXPECT_TRUE(std::isnan(w[0]) && std::isnan(w[1]) && std::isnan(w[2]));
}

TEST(GazeEvents, KappaByHand) {
  const std::vector<ET> a = {ET::fixation, ET::fixation, ET::fixation, ET::saccade,  ET::saccade,
                             ET::fixation, ET::fixation, ET::blink,    ET::fixation, ET::fixation};
  const std::vector<ET> b = {ET::fixation, ET::fixation, ET::saccade,  ET::saccade,  ET::saccade,
                             ET::fixation, ET::fixation, ET::fixation, ET::fixation, ET::blink};
  // Fixation: both 5, a only 2, b only 1, neither 2 of 10. p_o = 0.7; p_e = 0.7 * 0.6 + 0.3 * 0.4 = 0.54;
  // kappa = 0.16 / 0.46 = 8 / 23.
  EXPECT_NEAR(cohen_kappa(a, b, ET::fixation), 8.0 / 23.0, 1e-15);
  // Saccade: both 2, b only 1, neither 7. p_o = 0.9; p_e = 0.2 * 0.3 + 0.8 * 0.7 = 0.62; kappa = 14 / 19.
  EXPECT_NEAR(cohen_kappa(a, b, ET::saccade), 14.0 / 19.0, 1e-15);
  // Blink: both 0, a only 1, b only 1, neither 8. p_o = 0.8; p_e = 0.01 + 0.81 = 0.82; kappa = -1 / 9.
  EXPECT_NEAR(cohen_kappa(a, b, ET::blink), -1.0 / 9.0, 1e-15);
  EXPECT_DOUBLE_EQ(cohen_kappa(a, a, ET::saccade), 1.0);
  EXPECT_TRUE(std::isnan(cohen_kappa(a, b, ET::pursuit)));  // neither labeling has any: undefined
  EXPECT_TRUE(std::isnan(cohen_kappa(a, {ET::fixation}, ET::fixation)));
}

TEST(GazeEvents, ParameterErrors) {
  std::vector<ET> truth;
  const Recording r = constructed(truth);
  EventParams p;
  p.ivt.velocity_threshold_deg_s = -1;
  try {
    detect_events(r, p);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.param(), "velocity_threshold_deg_s");
    EXPECT_STREQ(e.what(), "velocity_threshold_deg_s must be in (0, 5000], not -1");
  }
  Recording px = r;
  px.units = Units::px;
  px.geometry.width_px = 1024, px.geometry.height_px = 768;
  try {
    detect_events(px, EventParams{});
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.param(), "geometry");
  }
  // Windows in samples are bounded (limits::kMaxGazeWindowSamples = 100,000): 1 µs steps make the
  // 1000 ms Savitzky-Golay window 1,000,000 samples and the 10 s I-DT window 10,000,000.
  Recording fine;
  fine.units = Units::deg;
  fine.t_ms = {0, 0.001, 0.002}, fine.x = {0, 0, 0}, fine.y = {0, 0, 0}, fine.valid = {1, 1, 1};
  EventParams a;
  a.method = Method::adaptive;
  a.adaptive.filter_window_ms = 1000;
  try {
    detect_events(fine, a);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.param(), "filter_window_ms");
    EXPECT_STREQ(
        e.what(),
        "filter_window_ms of 1000 ms holds more than limits::kMaxGazeWindowSamples (100000) samples");
  }
  EventParams i;
  i.method = Method::idt;
  i.idt.min_duration_ms = 10000;
  try {
    detect_events(fine, i);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.param(), "min_duration_ms");
  }
  try {
    parse_method("i-vt");
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "method must be ivt, idt or adaptive, not \"i-vt\"");
  }
}

}  // namespace
}  // namespace trailscope::gaze
