// Run comparison (analysis/run_compare): hand-made logs whose disagreements, errors and differences are
// known by construction — the expected numbers below are worked out by hand from the offsets put in.
#include <cmath>

#include <gtest/gtest.h>

#include "trailscope/analysis/run_compare.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::analysis {
namespace {

using tracker::State;
using tracker::TrackerLog;

/// The true tip of teat t in frame i: a square of 100 mm sides 500 mm away, drifting 1 mm a frame.
std::array<double, 3> true_tip(std::size_t i, int t) {
  return {(t % 2) * 100.0 + static_cast<double>(i), (t / 2) * 100.0, 500.0};
}

/// A log of `frames` frames from `first`, every teat reported exactly at the truth and in TRACK.
TrackerLog perfect_log(std::size_t first, std::size_t frames, double ncc_min = 0.35,
                       const std::string& video = "v1") {
  TrackerLog log;
  log.header.video_id = video;
  log.header.params = {{"ncc_min", ncc_min}, {"n_lost", 4}};
  for (std::size_t k = 0; k < frames; ++k) {
    tracker::FrameLog f;
    f.index = first + k;
    f.state = State::track;
    f.matches = 6;
    f.times.detect_us = 500;  // 2,000 frames/s
    tof::FrameTruth truth;
    for (int t = 0; t < tof::kTeatCount; ++t) {
      f.teats[t].tip_mm = true_tip(f.index, t);
      f.teats[t].visible = f.teats[t].tracked = true;
      truth.teats[t].tip_mm = true_tip(f.index, t);
      truth.teats[t].visible = true;
    }
    log.frames.push_back(f);
    log.truth.push_back(truth);
  }
  log.header.frame_count = frames;
  return log;
}

TEST(RunCompare, DisagreementsAreRankedByTheirScore) {
  TrackerLog a = perfect_log(0, 10), b = perfect_log(0, 10, 0.5), c = perfect_log(0, 10);
  for (std::size_t i : {3, 4, 5}) b.frames[i].teats[0].tip_mm[0] += 30;  // B 30 mm off on FL
  c.frames[7].teats[1].visible = false;                                  // C misses FR
  c.frames[7].state = State::lost;
  const Comparison cmp = compare_runs({&a, &b, &c});
  EXPECT_EQ(cmp.video, "v1");
  EXPECT_EQ(cmp.first_frame, 0u);
  EXPECT_EQ(cmp.frames, 10u);
  // Frames 3–5: FL spread 30 → 7.5. Frame 7: FR seen by A and B (together), missed by one run of three →
  // 50 / 3; mean over four teats 25 / 6.
  ASSERT_EQ(cmp.disagreements.size(), 4u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(cmp.disagreements[k].frame, k + 3);  // equal scores: earlier frame first
    EXPECT_NEAR(cmp.disagreements[k].score_mm, 7.5, 1e-12);
    EXPECT_EQ(cmp.disagreements[k].worst_teat, 0);
  }
  EXPECT_EQ(cmp.disagreements[3].frame, 7u);
  EXPECT_NEAR(cmp.disagreements[3].score_mm, 25.0 / 6.0, 1e-12);
  EXPECT_EQ(cmp.disagreements[3].worst_teat, 1);
  EXPECT_EQ(cmp.disagreements[3].states, (std::vector<int>{1, 1, 2}));
  // The series: B's FL error is its offset, C's FR in frame 7 is a miss (NaN per teat, +inf as the max).
  ASSERT_EQ(cmp.series.size(), 3u);
  EXPECT_NEAR(cmp.series[1].teat_error_mm[4][0], 30.0, 1e-12);
  EXPECT_NEAR(cmp.series[1].max_error_mm[4], 30.0, 1e-12);
  EXPECT_DOUBLE_EQ(cmp.series[0].max_error_mm[4], 0.0);
  EXPECT_TRUE(std::isnan(cmp.series[2].teat_error_mm[7][1]));
  EXPECT_TRUE(std::isinf(cmp.series[2].max_error_mm[7]));
  EXPECT_EQ(cmp.series[2].state[7], 2);
  EXPECT_EQ(cmp.series[0].matches, std::vector<int>(10, 6));
  // Top limits the list.
  CompareOptions top1;
  top1.top = 1;
  EXPECT_EQ(compare_runs({&a, &b, &c}, top1).disagreements.size(), 1u);
}

TEST(RunCompare, ParameterAndResultDifferencesSideBySide) {
  TrackerLog a = perfect_log(0, 10), b = perfect_log(0, 10, 0.5);
  for (std::size_t i = 0; i < 4; ++i) b.frames[i].state = State::lost;  // one LOST episode, 60 % TRACK
  b.frames[9].teats[2].tip_mm[2] += 20;                                 // one error of 20 mm
  const Comparison cmp = compare_runs({&a, &b});
  ASSERT_EQ(cmp.params.size(), 2u);
  EXPECT_EQ(cmp.params[0].name, "ncc_min");  // the differing one first
  EXPECT_TRUE(cmp.params[0].differs);
  EXPECT_EQ(cmp.params[0].values, (std::vector<double>{0.35, 0.5}));
  EXPECT_FALSE(cmp.params[1].differs);
  const auto row = [&](const std::string& name) {
    for (const ValueRow& r : cmp.results)
      if (r.name == name) return r;
    ADD_FAILURE() << "no result row " << name;
    return ValueRow{};
  };
  EXPECT_EQ(row("track_share").values, (std::vector<double>{1.0, 0.6}));
  EXPECT_EQ(row("lost_episodes").values, (std::vector<double>{0, 1}));
  EXPECT_NEAR(row("tracker_fps").values[0], 2000.0, 1e-9);
  EXPECT_FALSE(row("tracker_fps").differs);
  // B: 40 pairs, 39 exact and one of 20 mm; frames within 10 mm: 9 of 10.
  EXPECT_EQ(row("accuracy.median_error_mm").values, (std::vector<double>{0, 0}));
  EXPECT_NEAR(row("accuracy.frames_all_within").values[1], 0.9, 1e-12);
  EXPECT_TRUE(row("accuracy.p95_error_mm").values[1] == 0.0);  // 95th of 39 zeros and one 20: still 0
  EXPECT_TRUE(row("accuracy.frames_all_within").differs);
}

TEST(RunCompare, RunsAreComparedOnTheFramesTheyShare) {
  TrackerLog a = perfect_log(0, 10), b = perfect_log(4, 10);
  b.frames[0].teats[3].tip_mm[1] += 8;  // frame 4
  const Comparison cmp = compare_runs({&a, &b});
  EXPECT_EQ(cmp.first_frame, 4u);
  EXPECT_EQ(cmp.frames, 6u);
  ASSERT_EQ(cmp.series[0].state.size(), 6u);
  ASSERT_EQ(cmp.disagreements.size(), 1u);
  EXPECT_EQ(cmp.disagreements[0].frame, 4u);
  EXPECT_DOUBLE_EQ(cmp.disagreements[0].score_mm, 2.0);
  EXPECT_NEAR(cmp.series[1].teat_error_mm[0][3], 8.0, 1e-12);
  // Without ground truth the error series are empty and the accuracy figures NaN.
  a.truth.clear();
  const Comparison no_truth = compare_runs({&a, &b});
  EXPECT_TRUE(no_truth.series[0].max_error_mm.empty());
  EXPECT_EQ(no_truth.series[1].max_error_mm.size(), 6u);
}

TEST(RunCompare, BadInputIsRefusedNamingTheCause) {
  const TrackerLog a = perfect_log(0, 10), other_video = perfect_log(0, 10, 0.35, "v2"),
                   late = perfect_log(20, 5);
  TrackerLog gap = perfect_log(0, 10);
  gap.frames.erase(gap.frames.begin() + 5);
  gap.truth.erase(gap.truth.begin() + 5);
  const auto expect = [](auto&& f, Error::Kind kind, const std::string& param, const std::string& detail) {
    try {
      f();
      ADD_FAILURE() << "no error for " << param;
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), kind);
      EXPECT_EQ(e.param(), param);
      EXPECT_EQ(std::string(e.what()), detail);
    }
  };
  expect([&] { compare_runs({&a}); }, Error::Kind::invalid_argument, "runs",
         "runs: compare 2 to 8 runs, got 1");
  expect(
      [&] {
        compare_runs({&a, &other_video});
      },
      Error::Kind::unprocessable, "runs",
      "runs: run 2 is of video 'v2', run 1 of 'v1'; only runs of one video compare");
  expect(
      [&] {
        compare_runs({&a, &late});
      },
      Error::Kind::unprocessable, "runs", "runs: the runs share no frame");
  expect(
      [&] {
        compare_runs({&a, &gap});
      },
      Error::Kind::unprocessable, "runs", "runs: run 2 skips from frame 4 to 6");
  CompareOptions o;
  o.top = 0;
  expect(
      [&] {
        compare_runs({&a, &a}, o);
      },
      Error::Kind::invalid_argument, "top", "top: must be in [1, 1000], got 0");
  o = {};
  o.miss_mm = -1;
  expect(
      [&] {
        compare_runs({&a, &a}, o);
      },
      Error::Kind::invalid_argument, "miss_mm", "miss_mm: must be a finite distance > 0 mm");
}

TEST(RunCompare, JsonCarriesMissesAsInfinityAndGapsAsNull) {
  TrackerLog a = perfect_log(0, 3), b = perfect_log(0, 3);
  b.frames[1].teats[0].visible = false;
  const nlohmann::json j = to_json(compare_runs({&a, &b}));
  EXPECT_EQ(j["state_names"], nlohmann::json({"SEARCH", "TRACK", "LOST"}));
  EXPECT_EQ(j["series"][1]["max_error_mm"][1], "Infinity");
  EXPECT_EQ(j["series"][1]["teat_error_mm"][1][0], nullptr);
  EXPECT_EQ(j["series"][1]["teat_error_mm"][1][1], 0.0);
  EXPECT_EQ(j["disagreements"][0]["worst_teat"], "FL");
  EXPECT_EQ(j["disagreements"][0]["score_mm"], 6.25);  // a miss by one run of two: 50 / 2, over four teats
  EXPECT_EQ(j["params"][0]["name"], "ncc_min");
}

}  // namespace
}  // namespace trailscope::analysis
