// run_tracker on a small synthetic video, and params_of: what a run's header records, and that the log
// survives a write and a read in both encodings.
#include <gtest/gtest.h>

#include <regex>

#include "log_fixture.hpp"
#include "test_support.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/tof/synth.hpp"

namespace trailscope::tracker {
namespace {
namespace fs = std::filesystem;

/// One 60-frame synthetic video ("clip", standard scenario) shared by the tests of this file.
class RunTracker : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new trailscope::test::TempDir();
    tof::SynthOptions s;
    s.frames = 60;
    s.seed = 7;
    tof::write_synthetic_video(s, video(), tof::WriteOptions{});
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static fs::path video() { return dir_->path() / "clip"; }
  static inline trailscope::test::TempDir* dir_ = nullptr;
};

TEST_F(RunTracker, HeaderFramesAndTruth) {
  TrackerParams p;
  p.ncc_min = 0.6;
  std::vector<double> fractions;
  const TrackerLog log = run_tracker(video(), p, {}, [&](double f, std::string_view stage) {
    EXPECT_EQ(stage, "track");
    fractions.push_back(f);
  });
  const tof::DepthVideoReader reader(video());
  const RunHeader& h = log.header;
  EXPECT_EQ(h.version, kTrackerLogVersion);
  EXPECT_TRUE(std::regex_match(h.run_id, std::regex(R"(run-\d{8}-\d{6}-[0-9a-f]{4})"))) << h.run_id;
  EXPECT_TRUE(std::regex_match(h.created_utc, std::regex(R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ)")))
      << h.created_utc;
  EXPECT_EQ(h.video_id, "clip");
  EXPECT_EQ(h.tracker_version, kTrackerVersion);
  ASSERT_EQ(h.params.size(), parameter_infos().size());
  for (std::size_t i = 0; i < h.params.size(); ++i) EXPECT_EQ(h.params[i].name, parameter_infos()[i].name);
  EXPECT_EQ(get_param(params_of(h), "ncc_min"), 0.6);
  EXPECT_EQ(h.template_bank.size(), static_cast<std::size_t>(p.templates));
  EXPECT_EQ(h.intrinsics.fx, reader.info().intrinsics.fx);
  EXPECT_EQ(h.intrinsics.width, 176);
  EXPECT_EQ(h.fps, 25.0);
  EXPECT_EQ(h.video_source, reader.info().source);
  EXPECT_EQ(h.frame_count, 60u);
  ASSERT_EQ(log.frames.size(), 60u);
  ASSERT_EQ(log.truth.size(), 60u);
  for (std::size_t i = 0; i < 60; ++i) {
    EXPECT_EQ(log.frames[i].index, i);
    EXPECT_EQ(log.frames[i].timestamp_s, static_cast<double>(i) / 25.0);
    ASSERT_TRUE(log.truth[i].has_value());
    EXPECT_EQ(*log.truth[i], *reader.read_frame(i).truth);
  }
  // Progress: from 0 to 1, never backwards, about every 1 %.
  ASSERT_GE(fractions.size(), 2u);
  EXPECT_EQ(fractions.front(), 0.0);
  EXPECT_EQ(fractions.back(), 1.0);
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
  EXPECT_EQ(evaluate_accuracy(log).frames, 60u);

  for (const char* name : {"run.tslog", "run.json"}) {
    write_log(log, dir_->path() / name);
    test::expect_same_log(read_log(dir_->path() / name), log);
  }
}

TEST_F(RunTracker, FrameRangeAndIds) {
  RunOptions o;
  o.first_frame = 50;
  o.run_id = "run-a";
  o.video_id = "video-7";
  const TrackerLog tail = run_tracker(video(), {}, o);
  EXPECT_EQ(tail.header.run_id, "run-a");
  EXPECT_EQ(tail.header.video_id, "video-7");
  ASSERT_EQ(tail.frames.size(), 10u);
  EXPECT_EQ(tail.frames.front().index, 50u) << "video frame numbers, not run-relative ones";
  EXPECT_EQ(tail.truth.size(), 10u);
  o.frame_count = 3;
  EXPECT_EQ(run_tracker(video(), {}, o).frames.size(), 3u);

  auto expect_param = [&](const RunOptions& bad, const char* param) {
    try {
      run_tracker(video(), {}, bad);
      ADD_FAILURE() << param;
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), Error::Kind::invalid_argument);
      EXPECT_EQ(e.param(), param) << e.what();
    }
  };
  expect_param({"", "", 60, 0}, "first_frame");
  expect_param({"", "", 55, 10}, "frame_count");
  TrackerParams bad;
  bad.ncc_min = 2;
  EXPECT_THROW(run_tracker(video(), bad), Error);
}

TEST(ParamsOf, RoundTripsAndChecks) {
  TrackerParams p;
  p.ncc_min = 0.7;
  p.templates = 6;
  p.d_gate_mm = 30;
  RunHeader h;
  const std::vector<double> v = to_vector(p);
  for (std::size_t i = 0; i < v.size(); ++i) h.params.push_back({parameter_infos()[i].name, v[i]});
  EXPECT_EQ(to_vector(params_of(h)), v);
  // Unknown names (another tracker version's) are ignored; missing ones keep their defaults.
  h.params = {{"no_such_param", 1}, {"ncc_min", 0.65}};
  const TrackerParams q = params_of(h);
  EXPECT_EQ(q.ncc_min, 0.65);
  EXPECT_EQ(q.templates, TrackerParams{}.templates);
  h.params = {{"ncc_min", 1.5}};
  try {
    params_of(h);
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::invalid_argument);
    EXPECT_EQ(e.param(), "ncc_min");
  }
}

}  // namespace
}  // namespace trailscope::tracker
