// POST /api/v1/compare in process: two uploaded runs of one video, one 25 mm off on a teat in three frames,
// come back aligned with their rows, and those frames ranked; refusals name their field.
#include <gtest/gtest.h>

#include "tracker_fixture.hpp"
#include "trailscope/tracker/tracker_log.hpp"

namespace trailscope::server {
namespace {

class CompareTest : public test_routes::TrackerFixture {
 protected:
  Response compare(const nlohmann::json& body) { return send("POST", "/api/v1/compare", body.dump()); }

  /// Uploads a 20-frame log of `video`; teat RL is `offset_mm` off in x in frames 10–12. Returns the id.
  std::string upload_log(const std::string& video, double ncc, double offset_mm) {
    tracker::TrackerLog log;
    log.header.video_id = video;
    log.header.params = {{"ncc_min", ncc}, {"n_lost", 4}};
    for (std::size_t i = 0; i < 20; ++i) {
      tracker::FrameLog f;
      f.index = i;
      f.state = tracker::State::track;
      for (int t = 0; t < 4; ++t) {
        f.teats[t].tip_mm = {t * 50.0, 0.0, 400.0};
        f.teats[t].visible = f.teats[t].tracked = true;
      }
      if (i >= 10 && i <= 12) f.teats[2].tip_mm[0] += offset_mm;
      log.frames.push_back(f);
    }
    log.header.frame_count = log.frames.size();
    const Response r = send("POST", "/api/v1/runs", tracker::encode_log(log, tracker::LogEncoding::json));
    EXPECT_EQ(r.status, 201) << r.body;
    return body(r).at("id").get<std::string>();
  }
};

TEST_F(CompareTest, RunsComeBackAlignedWithTheirDisagreementsRanked) {
  const std::string a = upload_log("v1", 0.35, 0), b = upload_log("v1", 0.5, 25);
  const Response r = compare({{"runs", {b, a}}, {"top", 2}});
  ASSERT_EQ(r.status, 200) << r.body;
  const auto j = body(r);
  EXPECT_EQ(j["video"], "v1");
  EXPECT_EQ(j["frames"], 20);
  ASSERT_EQ(j["runs"].size(), 2u);
  EXPECT_EQ(j["runs"][0]["id"], b);  // the order asked for
  EXPECT_EQ(j["series"][0]["id"], b);
  EXPECT_EQ(j["series"][1]["state"].size(), 20u);
  ASSERT_EQ(j["disagreements"].size(), 2u);  // three frames disagree, top 2 listed
  EXPECT_EQ(j["disagreements"][0]["frame"], 10);
  EXPECT_EQ(j["disagreements"][1]["frame"], 11);
  EXPECT_DOUBLE_EQ(j["disagreements"][0]["score_mm"].get<double>(), 25.0 / 4);
  EXPECT_EQ(j["disagreements"][0]["worst_teat"], "RL");
  EXPECT_EQ(j["params"][0]["name"], "ncc_min");
  EXPECT_EQ(j["params"][0]["values"], nlohmann::json({0.5, 0.35}));
  EXPECT_EQ(j["series"][0]["max_error_mm"], nlohmann::json::array());  // no ground truth in these logs
}

TEST_F(CompareTest, BadRequestsNameTheirField) {
  const std::string a = upload_log("v1", 0.35, 0), other = upload_log("v2", 0.35, 0);
  expect_detail(compare(nlohmann::json::object()), 400, "invalid_argument", "runs",
                "runs: required, an array of 2 to 8 run ids");
  expect_detail(compare({{"runs", {a}}}), 400, "invalid_argument", "runs",
                "runs: compare 2 to 8 runs, got 1");
  expect_detail(compare({{"runs", {a, 3}}}), 400, "invalid_argument", "runs",
                "runs: must be an array of run ids");
  expect_detail(compare({{"runs", {a, other}}}), 422, "unprocessable", "runs",
                "runs: run 2 is of video 'v2', run 1 of 'v1'; only runs of one video compare");
  expect_error(compare({{"runs", {a, "r99"}}}), 404, "not_found", "run");
  expect_detail(compare({{"runs", {a, a}}, {"top", 0}}), 400, "invalid_argument", "top",
                "top: must be in [1, 1000]");
  expect_detail(compare({{"runs", {a, a}}, {"miss_mm", "far"}}), 400, "invalid_argument", "miss_mm",
                "miss_mm: must be a number");
  expect_detail(compare({{"runs", {a, a}}, {"within", 3}}), 400, "invalid_argument", "within",
                "unknown field 'within'");
}

}  // namespace
}  // namespace trailscope::server
