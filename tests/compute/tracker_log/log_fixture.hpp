#pragma once
// Hand-built tracker logs for the format tests, and a field-by-field comparison that treats NaN as equal
// to NaN (the log's "missing"). Every field gets a distinct non-default value, so a field the encoder or
// decoder forgets shows up as a mismatch.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "trailscope/tracker/tracker_log.hpp"

namespace trailscope::tracker::test {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Frame `i` with values derived from i; frame 1 has no candidates, odd frames have NaN pair distances.
inline FrameLog sample_frame(std::size_t i) {
  const double b = 10.0 * static_cast<double>(i);
  FrameLog f;
  f.index = 100 + i;
  f.timestamp_s = 4.0 + 0.04 * static_cast<double>(i);
  f.valid_pixels = 20000 + static_cast<int>(i);
  f.flying_pixels = 31 + static_cast<int>(i);
  f.matches = 7;
  f.verified = 5;
  if (i != 1) {
    for (int k = 0; k < 2; ++k) {
      Candidate c;
      c.u = 12.25 + b + k;
      c.v = 80.5 - k;
      c.ncc = 0.8125 - 0.1 * k;
      c.template_index = k + 1;
      c.verified = k == 0;
      c.tip_mm = {-31.5 + b, 12.75, 301.0 + k};
      c.axis = {0.6, 0.0, -0.8};
      c.radius_mm = 9.5;
      c.fit_rms_mm = 1.0 / 3.0;  // not a short decimal: the JSON must still round-trip it exactly
      c.points = 140 + k;
      c.teat = k == 0 ? 2 : -1;
      f.candidates.push_back(c);
    }
  }
  for (int p = 0; p < 6; ++p) {
    f.model.pair_mm[p] = (i % 2 == 1 && p >= 4) ? kNaN : 50.0 + p + b;
    f.model.pair_error_mm[p] = (i % 2 == 1 && p >= 4) ? kNaN : 0.5 * p;
  }
  f.model.shape_cost = 1.25;
  f.model.ncc_cost = 0.1875;
  f.model.cost = 1.25 + 20 * 0.1875;
  f.model.teats_matched = 3;
  f.state = i % 3 == 0 ? State::search : (i % 3 == 1 ? State::track : State::lost);
  for (int t = 0; t < tof::kTeatCount; ++t) {
    TeatEstimate& e = f.teats[t];
    e.tip_mm = {10.0 * t + b, -5.5 * t, 250.0 + t};
    e.tip_px = {88.0 + t, 72.0 - t};
    e.visible = t != 3;
    e.tracked = t != 2;
    e.confidence = 0.25 * t;
    e.radius_mm = 8.0 + t;
  }
  f.times = {120.5, 850.25, 300.0, 12.125};
  return f;
}

inline tof::FrameTruth sample_truth(std::size_t i) {
  tof::FrameTruth ft;
  for (int t = 0; t < tof::kTeatCount; ++t) {
    tof::TeatTruth& tt = ft.teats[t];
    tt.tip_mm = {10.0 * t + 1.5, -5.5 * t, 251.0 + static_cast<double>(i)};
    if (t != 1) tt.tip_px = std::array<double, 2>{88.5 + t, 71.5};
    tt.visible = t != 0;
    if (t != 3) tt.box_px = tof::BoxPx{80.5 + t, 60.5, 12, 20};
    tt.visible_fraction = 0.125 * t;
    tt.cup_attached = t == 2;
  }
  return ft;
}

/// Four frames; truth on all but frame 2 when `with_truth`.
inline TrackerLog sample_log(bool with_truth = true) {
  TrackerLog log;
  RunHeader& h = log.header;
  h.run_id = "run-20261122-155900-3f2a";
  h.video_id = "standard-60";
  h.params = {{"ncc_min", 0.6}, {"templates", 3}, {"z_max_mm", 850.5}};
  h.template_bank = {{3.0, 7}, {5.5, 13}, {9.25, 19}};
  h.intrinsics = {150.0, 151.5, 87.5, 71.5, 176, 144, true};
  h.fps = 25;
  h.created_utc = "2026-11-22T15:59:00Z";
  // A 64-bit seed beyond 2^53: the reason video_source is JSON text, not a protobuf Struct.
  h.video_source = {
      {"generator", "trailscope synth"}, {"scenario", "standard"}, {"seed", 18446744073709551557ull}};
  for (std::size_t i = 0; i < 4; ++i) {
    log.frames.push_back(sample_frame(i));
    if (with_truth) log.truth.push_back(i == 2 ? std::nullopt : std::optional(sample_truth(i)));
  }
  h.frame_count = log.frames.size();
  return log;
}

inline bool same(double a, double b) {
  return (std::isnan(a) && std::isnan(b)) || a == b;
}

template <std::size_t N>
bool same(const std::array<double, N>& a, const std::array<double, N>& b) {
  for (std::size_t k = 0; k < N; ++k)
    if (!same(a[k], b[k])) return false;
  return true;
}

inline void expect_same_header(const RunHeader& a, const RunHeader& b) {
  EXPECT_EQ(a.version, b.version);
  EXPECT_EQ(a.run_id, b.run_id);
  EXPECT_EQ(a.video_id, b.video_id);
  EXPECT_EQ(a.tracker_version, b.tracker_version);
  ASSERT_EQ(a.params.size(), b.params.size());
  for (std::size_t i = 0; i < a.params.size(); ++i) {
    EXPECT_EQ(a.params[i].name, b.params[i].name);
    EXPECT_TRUE(same(a.params[i].value, b.params[i].value)) << a.params[i].name;
  }
  ASSERT_EQ(a.template_bank.size(), b.template_bank.size());
  for (std::size_t i = 0; i < a.template_bank.size(); ++i) {
    EXPECT_EQ(a.template_bank[i].radius_px, b.template_bank[i].radius_px);
    EXPECT_EQ(a.template_bank[i].size_px, b.template_bank[i].size_px);
  }
  EXPECT_EQ(a.intrinsics.fx, b.intrinsics.fx);
  EXPECT_EQ(a.intrinsics.fy, b.intrinsics.fy);
  EXPECT_EQ(a.intrinsics.cx, b.intrinsics.cx);
  EXPECT_EQ(a.intrinsics.cy, b.intrinsics.cy);
  EXPECT_EQ(a.intrinsics.width, b.intrinsics.width);
  EXPECT_EQ(a.intrinsics.height, b.intrinsics.height);
  EXPECT_EQ(a.intrinsics.defaulted, b.intrinsics.defaulted);
  EXPECT_EQ(a.fps, b.fps);
  EXPECT_EQ(a.frame_count, b.frame_count);
  EXPECT_EQ(a.created_utc, b.created_utc);
  EXPECT_EQ(a.video_source, b.video_source);
}

/// `with_times`: stage times are wall times, so logs of two runs are compared without them.
inline void expect_same_frame(const FrameLog& a, const FrameLog& b, bool with_times = true) {
  SCOPED_TRACE("frame " + std::to_string(a.index));
  EXPECT_EQ(a.index, b.index);
  EXPECT_EQ(a.timestamp_s, b.timestamp_s);
  EXPECT_EQ(a.valid_pixels, b.valid_pixels);
  EXPECT_EQ(a.flying_pixels, b.flying_pixels);
  EXPECT_EQ(a.matches, b.matches);
  EXPECT_EQ(a.verified, b.verified);
  ASSERT_EQ(a.candidates.size(), b.candidates.size());
  for (std::size_t k = 0; k < a.candidates.size(); ++k) {
    const Candidate &x = a.candidates[k], &y = b.candidates[k];
    EXPECT_TRUE(same(x.u, y.u) && same(x.v, y.v) && same(x.ncc, y.ncc)) << "candidate " << k;
    EXPECT_EQ(x.template_index, y.template_index);
    EXPECT_EQ(x.verified, y.verified);
    EXPECT_TRUE(same(x.tip_mm, y.tip_mm) && same(x.axis, y.axis)) << "candidate " << k;
    EXPECT_TRUE(same(x.radius_mm, y.radius_mm) && same(x.fit_rms_mm, y.fit_rms_mm)) << "candidate " << k;
    EXPECT_EQ(x.points, y.points);
    EXPECT_EQ(x.teat, y.teat);
  }
  EXPECT_TRUE(same(a.model.pair_mm, b.model.pair_mm));
  EXPECT_TRUE(same(a.model.pair_error_mm, b.model.pair_error_mm));
  EXPECT_TRUE(same(a.model.shape_cost, b.model.shape_cost));
  EXPECT_TRUE(same(a.model.ncc_cost, b.model.ncc_cost));
  EXPECT_TRUE(same(a.model.cost, b.model.cost));
  EXPECT_EQ(a.model.teats_matched, b.model.teats_matched);
  EXPECT_EQ(a.state, b.state);
  for (int t = 0; t < tof::kTeatCount; ++t) {
    const TeatEstimate &x = a.teats[t], &y = b.teats[t];
    EXPECT_TRUE(same(x.tip_mm, y.tip_mm) && same(x.tip_px, y.tip_px)) << "teat " << t;
    EXPECT_EQ(x.visible, y.visible) << "teat " << t;
    EXPECT_EQ(x.tracked, y.tracked) << "teat " << t;
    EXPECT_TRUE(same(x.confidence, y.confidence) && same(x.radius_mm, y.radius_mm)) << "teat " << t;
  }
  if (with_times) {
    EXPECT_EQ(a.times.preprocess_us, b.times.preprocess_us);
    EXPECT_EQ(a.times.detect_us, b.times.detect_us);
    EXPECT_EQ(a.times.verify_us, b.times.verify_us);
    EXPECT_EQ(a.times.model_us, b.times.model_us);
  }
}

inline void expect_same_log(const TrackerLog& a, const TrackerLog& b, bool with_times = true) {
  expect_same_header(a.header, b.header);
  ASSERT_EQ(a.frames.size(), b.frames.size());
  for (std::size_t i = 0; i < a.frames.size(); ++i) expect_same_frame(a.frames[i], b.frames[i], with_times);
  // FrameTruth has operator== (exact doubles; truth never holds NaN).
  EXPECT_EQ(a.truth, b.truth);
}

}  // namespace trailscope::tracker::test
