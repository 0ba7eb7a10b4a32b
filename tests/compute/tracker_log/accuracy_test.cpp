// evaluate_accuracy against a six-frame log whose figures were computed by hand (errors are 3-4-5 and
// 5-12-13 triangles, so every distance is a whole number of mm).
#include <gtest/gtest.h>

#include <cmath>

#include "trailscope/core/error.hpp"
#include "trailscope/tracker/tracker_log.hpp"

namespace trailscope::tracker {
namespace {

constexpr std::array<double, 3> kTip = {10, -20, 300};

/// One teat's truth at kTip, and the tracker's report `offset` away from it.
struct Teat {
  bool truth_visible;
  bool reported;
  std::array<double, 3> offset;
};

TrackerLog hand_log() {
  const State S = State::search, T = State::track, L = State::lost;
  struct Row {
    State state;
    bool has_truth;
    std::array<Teat, 4> teats;
  };
  const std::array<double, 3> e0{0, 0, 0}, e3{3, 0, 0}, e4{0, 0, 4}, e5{3, 4, 0}, e12{0, 12, 0},
      e13{5, 12, 0}, far{100, 0, 0};
  const Row rows[] = {
      // frame 0: FL 3, FR 5; RL/RR not visible in truth (the tracker's far reports must be ignored)
      {S, true, {{{true, true, e3}, {true, true, e5}, {false, true, far}, {false, false, far}}}},
      // frame 1: FL 4, FR visible but missed (+inf), RL 12
      {T, true, {{{true, true, e4}, {true, false, far}, {true, true, e12}, {false, false, e0}}}},
      // frame 2: no truth at all
      {L, false, {{{true, true, far}, {true, true, far}, {true, true, far}, {true, true, far}}}},
      // frame 3: truth, but nothing visible
      {L, true, {{{false, true, far}, {false, false, e0}, {false, false, e0}, {false, false, e0}}}},
      // frame 4: FL 13, FR 3, RL 4, RR 5
      {T, true, {{{true, true, e13}, {true, true, e3}, {true, true, e4}, {true, true, e5}}}},
      // frame 5: RR 0
      {L, true, {{{false, false, e0}, {false, false, e0}, {false, false, e0}, {true, true, e0}}}},
  };
  TrackerLog log;
  std::size_t i = 0;
  for (const Row& r : rows) {
    FrameLog f;
    f.index = i++;
    f.state = r.state;
    tof::FrameTruth truth;
    for (int t = 0; t < 4; ++t) {
      truth.teats[t].tip_mm = kTip;
      truth.teats[t].visible = r.teats[t].truth_visible;
      f.teats[t].visible = r.teats[t].reported;
      for (int k = 0; k < 3; ++k) f.teats[t].tip_mm[k] = kTip[k] + r.teats[t].offset[k];
    }
    log.frames.push_back(f);
    log.truth.push_back(r.has_truth ? std::optional(truth) : std::nullopt);
  }
  log.header.frame_count = log.frames.size();
  return log;
}

TEST(TrackerAccuracy, HandComputedFigures) {
  const Accuracy a = evaluate_accuracy(hand_log());
  EXPECT_EQ(a.frames, 5u);
  EXPECT_EQ(a.visible_pairs, 10u);
  EXPECT_EQ(a.reported_pairs, 9u);
  // errors {3, 5, 4, 12, 13, 3, 4, 5, 0}: sorted 0 3 3 4 4 5 5 12 13
  EXPECT_EQ(a.median_error_mm, 4.0);
  EXPECT_DOUBLE_EQ(a.mean_error_mm, 49.0 / 9.0);
  EXPECT_DOUBLE_EQ(a.p95_error_mm, 12.6);  // rank 0.95 * 8 = 7.6, between 12 and 13
  const std::size_t visible[] = {3, 3, 2, 2}, reported[] = {3, 2, 2, 2};
  const double median[] = {4, 4, 8, 2.5}, p95[] = {12.1, 4.9, 11.6, 4.75};
  for (int t = 0; t < 4; ++t) {
    SCOPED_TRACE(t);
    EXPECT_EQ(a.teats[t].visible_frames, visible[t]);
    EXPECT_EQ(a.teats[t].reported, reported[t]);
    EXPECT_DOUBLE_EQ(a.teats[t].median_error_mm, median[t]);
    EXPECT_DOUBLE_EQ(a.teats[t].p95_error_mm, p95[t]);
  }
  // Frames with a visible teat: 0 (worst 5), 1 (a miss), 4 (worst 13), 5 (worst 0).
  EXPECT_EQ(a.within_mm, 10.0);
  EXPECT_EQ(a.frames_all_within, 0.5);
  EXPECT_EQ(a.track_share, 2.0 / 6.0);
  EXPECT_EQ(a.lost_episodes, 2u);  // frames 2-3 and 5
  ASSERT_EQ(a.frame_max_error_mm.size(), 6u);
  EXPECT_EQ(a.frame_max_error_mm[0], 5.0);
  EXPECT_TRUE(std::isinf(a.frame_max_error_mm[1]) && a.frame_max_error_mm[1] > 0);
  EXPECT_TRUE(std::isnan(a.frame_max_error_mm[2]));
  EXPECT_TRUE(std::isnan(a.frame_max_error_mm[3]));
  EXPECT_EQ(a.frame_max_error_mm[4], 13.0);
  EXPECT_EQ(a.frame_max_error_mm[5], 0.0);
  // The threshold is inclusive.
  EXPECT_EQ(evaluate_accuracy(hand_log(), 13.0).frames_all_within, 0.75);
}

TEST(TrackerAccuracy, NoReportedPairsGiveNaN) {
  TrackerLog log = hand_log();
  for (auto& f : log.frames)
    for (auto& t : f.teats) t.visible = false;
  const Accuracy a = evaluate_accuracy(log);
  EXPECT_EQ(a.reported_pairs, 0u);
  EXPECT_TRUE(std::isnan(a.median_error_mm) && std::isnan(a.mean_error_mm) && std::isnan(a.p95_error_mm));
  EXPECT_TRUE(std::isnan(a.teats[0].median_error_mm));
  EXPECT_EQ(a.frames_all_within, 0.0);
}

TEST(TrackerAccuracy, JsonKeepsNaNAndInfinityApart) {
  const nlohmann::json j = to_json(evaluate_accuracy(hand_log()));
  EXPECT_EQ(j["frames"], 5);
  EXPECT_EQ(j["visible_pairs"], 10);
  EXPECT_EQ(j["reported_pairs"], 9);
  EXPECT_EQ(j["median_error_mm"], 4.0);
  EXPECT_EQ(j["frames_all_within"], 0.5);
  EXPECT_EQ(j["within_mm"], 10.0);
  EXPECT_EQ(j["lost_episodes"], 2);
  EXPECT_EQ(j["teats"][3]["name"], "RR");
  EXPECT_EQ(j["teats"][1]["reported"], 2);
  EXPECT_EQ(j["frame_max_error_mm"], nlohmann::json::parse(R"([5.0, "Infinity", "NaN", "NaN", 13.0, 0.0])"));
}

TEST(TrackerAccuracy, Errors) {
  TrackerLog log = hand_log();
  try {
    evaluate_accuracy(log, 0.0);
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::invalid_argument);
    EXPECT_EQ(e.param(), "within_mm");
  }
  log.truth.clear();
  try {
    evaluate_accuracy(log);
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::unprocessable);
    EXPECT_EQ(e.param(), "truth");
    EXPECT_STREQ(e.what(), "truth: the log has no ground truth");
  }
}

}  // namespace
}  // namespace trailscope::tracker
