// Parameter sweeps over the API, in process: a 6-point grid over two synthetic videos makes 12 stored runs
// tagged with the sweep, one per (point, video); cancelling stops it; the spec, the videos and the size are
// checked before the job starts.
#include <set>

#include <gtest/gtest.h>

#include "tracker_fixture.hpp"
#include "trailscope/tracker/params.hpp"

namespace trailscope::server {
namespace {

class SweepTest : public test_routes::TrackerFixture {
 protected:
  Response sweep(const nlohmann::json& videos, const nlohmann::json& spec) {
    return send("POST", "/api/v1/sweeps", nlohmann::json{{"videos", videos}, {"sweep", spec}}.dump());
  }
  static nlohmann::json grid6() {
    return {{"mode", "grid"},
            {"axes",
             {{{"param", "ncc_min"}, {"min", 0.4}, {"max", 0.6}, {"steps", 3}},
              {{"param", "n_lost"}, {"min", 4}, {"max", 6}, {"steps", 2}}}}};
  }
};

TEST_F(SweepTest, GridOverTwoVideosStoresEveryRun) {
  const std::string v1 = upload_video(12, 1), v2 = upload_video(12, 2);
  const Response r = sweep({v1, v2}, grid6());
  ASSERT_EQ(r.status, 202) << r.body;
  const auto j = body(r);
  EXPECT_EQ(j["job"]["kind"], "sweep");
  EXPECT_EQ(j["sweep"]["id"], "s1");
  EXPECT_EQ(j["sweep"]["total"], 12);
  EXPECT_EQ(header(r, "Location"), "/api/v1/sweeps/s1");
  const JobState done = app->jobs.wait(j["job"]["id"]);
  ASSERT_EQ(done.state, "done") << done.to_json().dump();
  EXPECT_DOUBLE_EQ(done.progress, 1.0);

  const auto s = body(get("/api/v1/sweeps/s1"));
  EXPECT_EQ(s["done"], true);
  EXPECT_EQ(s["state"], "done");
  EXPECT_EQ(s["videos"], nlohmann::json({v1, v2}));
  EXPECT_EQ(s["spec"]["mode"], "grid");
  EXPECT_EQ(s["spec"]["axes"].size(), 2u);
  ASSERT_EQ(s["runs"].size(), 12u);
  EXPECT_EQ(done.result, s);

  std::set<std::pair<std::string, std::vector<double>>> distinct;
  std::set<std::vector<double>> points;
  const auto names = body(get("/api/v1/runs"))["runs"][0]["param_names"].get<std::vector<std::string>>();
  const auto index = [&](const std::string& n) {
    return std::find(names.begin(), names.end(), n) - names.begin();
  };
  for (const auto& id : s["runs"]) {
    const auto row = body(get("/api/v1/runs/" + id.get<std::string>()));
    EXPECT_EQ(row["origin"], "sweep");
    EXPECT_EQ(row["sweep"], "s1");
    EXPECT_EQ(row["summary"]["frames"], 12);
    const auto params = row["params"].get<std::vector<double>>();
    const double ncc = params[index("ncc_min")], n_lost = params[index("n_lost")];
    EXPECT_TRUE(ncc == 0.4 || std::abs(ncc - 0.5) < 1e-12 || ncc == 0.6) << ncc;
    EXPECT_TRUE(n_lost == 4 || n_lost == 6) << n_lost;
    distinct.emplace(row["video"].get<std::string>(), params);
    points.insert(params);
  }
  EXPECT_EQ(distinct.size(), 12u);
  EXPECT_EQ(points.size(), 6u);
  EXPECT_EQ(body(get("/api/v1/sweeps"))["sweeps"].size(), 1u);

  // Importance over the sweep's runs: only ncc_min and n_lost vary.
  const Response imp = get("/api/v1/importance", {{"metric", "track_share"}, {"sweep", "s1"}});
  ASSERT_EQ(imp.status, 200) << imp.body;
  EXPECT_EQ(body(imp)["samples"], 12);
  EXPECT_EQ(body(imp)["sweep"], "s1");
  const auto importance = body(imp);  // named: a range-for over a temporary's member reads freed memory
  for (const auto& in : importance["inputs"])
    if (in["name"] != "ncc_min" && in["name"] != "n_lost") EXPECT_EQ(in["pearson"], nullptr) << in.dump();

  // The record survives a restart.
  open_empty();
  EXPECT_EQ(body(get("/api/v1/sweeps/s1"))["runs"].size(), 12u);
}

TEST_F(SweepTest, AFrameRangeMakesShortRuns) {
  const std::string v = upload_video(12);
  const Response r =
      send("POST", "/api/v1/sweeps",
           nlohmann::json{{"videos", {v}},
                          {"sweep", {{"mode", "random"}, {"samples", 2}, {"axes", {{{"param", "ncc_min"}}}}}},
                          {"first_frame", 3},
                          {"frame_count", 5}}
               .dump());
  ASSERT_EQ(r.status, 202) << r.body;
  EXPECT_EQ(body(r)["sweep"]["frames"], nlohmann::json({{"first_frame", 3}, {"frame_count", 5}}));
  ASSERT_EQ(app->jobs.wait(body(r)["job"]["id"]).state, "done");
  const auto sweep = body(get("/api/v1/sweeps/s1"));
  for (const auto& id : sweep["runs"]) {
    EXPECT_EQ(body(get("/api/v1/runs/" + id.get<std::string>()))["summary"]["frames"], 5);
    const auto frames = body(get("/api/v1/runs/" + id.get<std::string>() + "/frames"));
    EXPECT_EQ(frames["frames"][0]["index"], 3) << frames.dump().substr(0, 300);
  }
  const auto bad = [&](const nlohmann::json& range) {
    nlohmann::json b = {{"videos", {v}}, {"sweep", grid6()}};
    b.update(range);
    return send("POST", "/api/v1/sweeps", b.dump());
  };
  expect_detail(bad({{"first_frame", 12}}), 400, "invalid_argument", "first_frame",
                "first_frame: 12 is not a frame of video '" + v + "' (it has 12)");
  expect_detail(bad({{"first_frame", 10}, {"frame_count", 5}}), 400, "invalid_argument", "frame_count",
                "frame_count: 5 frames from frame 10 run past video '" + v + "' (12 frames)");
  expect_detail(bad({{"frame_count", -1}}), 400, "invalid_argument", "frame_count",
                "frame_count: must be ≥ 0 (0 = to the end)");
  expect_detail(bad({{"first_frame", 1.5}}), 400, "invalid_argument", "first_frame",
                "first_frame: must be an integer");
}

TEST_F(SweepTest, CancelStopsTheSweep) {
  const std::string v = upload_video(40);
  const Response r = sweep({v}, {{"mode", "random"}, {"samples", 200}, {"axes", {{{"param", "ncc_min"}}}}});
  ASSERT_EQ(r.status, 202) << r.body;
  const std::string job = body(r)["job"]["id"];
  ASSERT_EQ(send("DELETE", "/api/v1/jobs/" + job).status, 200);
  EXPECT_EQ(app->jobs.wait(job).state, "cancelled");
  const auto s = body(get("/api/v1/sweeps/s1"));
  EXPECT_EQ(s["state"], "cancelled");
  EXPECT_EQ(s["done"], false);
  EXPECT_LT(s["runs"].size(), 200u);
  EXPECT_EQ(body(get("/api/v1/runs"))["runs"].size(), s["runs"].size());
}

TEST_F(SweepTest, BadRequestsAreRefusedBeforeTheJob) {
  const std::string v = upload_video(5);
  expect_detail(sweep({v}, {{"mode", "spiral"}, {"axes", nlohmann::json::array()}}), 400, "invalid_argument",
                "mode", "mode must be \"grid\" or \"random\"");
  expect_detail(sweep({v}, {{"mode", "grid"}, {"axes", {{{"param", "no_such_param"}}}}}), 400,
                "invalid_argument", "axes", "unknown tracker parameter 'no_such_param' in axes");
  expect_error(sweep({v}, {{"mode", "grid"}}), 400, "invalid_argument", "axes");
  expect_detail(sweep({v, "v99"}, grid6()), 404, "not_found", "video", "video 'v99' does not exist");
  expect_detail(sweep(nlohmann::json::array(), grid6()), 400, "invalid_argument", "videos",
                "videos: must be a non-empty array of video ids");
  expect_detail(send("POST", "/api/v1/sweeps", nlohmann::json{{"videos", {v}}}.dump()), 400,
                "invalid_argument", "sweep", "sweep: required");
  expect_error(send("POST", "/api/v1/sweeps", R"({"videos": [")" + v + R"("], "sweep": {}, "x": 1})"), 400,
               "invalid_argument", "x");
  // Points x videos beyond kMaxSweepRuns.
  const std::size_t half = limits::kMaxSweepRuns / 2 + 1;
  expect_detail(sweep({v, v}, {{"mode", "random"}, {"samples", half}, {"axes", {{{"param", "ncc_min"}}}}}),
                413, "payload_too_large", "videos",
                std::to_string(half) + " points x 2 videos = " + std::to_string(2 * half) +
                    " runs, more than the limit of " + std::to_string(limits::kMaxSweepRuns) +
                    " (kMaxSweepRuns)");
  expect_detail(get("/api/v1/sweeps/s9"), 404, "not_found", "sweep", "sweep 's9' does not exist");
  EXPECT_EQ(body(get("/api/v1/sweeps"))["sweeps"].size(), 0u);
  EXPECT_EQ(app->jobs.list().size(), 0u);
}

}  // namespace
}  // namespace trailscope::server
