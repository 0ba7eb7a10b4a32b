// Tracker runs over the API, in process: the parameter list, track jobs over a stored video (parameters
// checked up front), the runs table with summaries, the log in both encodings, paged frames, log uploads
// (good and bad), deletion and persistence.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "tracker_fixture.hpp"
#include "trailscope/tracker/params.hpp"
#include "trailscope/tracker/tracker_log.hpp"

namespace trailscope::server {
namespace {

class RunsTest : public test_routes::TrackerFixture {
 protected:
  /// Tracks `video` with `params` (JSON object text) and returns the stored run's id.
  std::string track(const std::string& video, const std::string& params = "{}") {
    const Response r =
        send("POST", "/api/v1/runs/track", R"({"video": ")" + video + R"(", "params": )" + params + "}");
    EXPECT_EQ(r.status, 202) << r.body;
    if (r.status != 202) return "";
    EXPECT_EQ(body(r)["job"]["kind"], "track");
    const JobState done = app->jobs.wait(body(r)["job"]["id"]);
    EXPECT_EQ(done.state, "done") << done.to_json().dump();
    return done.result.value("id", "");
  }
};

TEST_F(RunsTest, ParameterList) {
  const Response r = get("/api/v1/tracker/params");
  ASSERT_EQ(r.status, 200);
  const auto list = body(r)["params"];
  ASSERT_EQ(list.size(), tracker::parameter_infos().size());
  for (std::size_t i = 0; i < list.size(); ++i) {
    const auto& info = tracker::parameter_infos()[i];
    EXPECT_EQ(list[i]["name"], info.name);
    EXPECT_EQ(list[i]["default"], info.default_number);
    EXPECT_EQ(list[i]["min"], info.min);
    EXPECT_EQ(list[i]["max"], info.max);
    EXPECT_EQ(list[i]["integer"], info.integer);
    EXPECT_TRUE(list[i].contains("unit") && list[i].contains("help"));
  }
}

TEST_F(RunsTest, TrackJobStoresARunWithItsSummary) {
  const std::string video = upload_video(40);
  const std::string id = track(video, R"({"ncc_min": 0.5, "n_lost": 6})");
  ASSERT_EQ(id, "r1");
  const auto rows = body(get("/api/v1/runs"))["runs"];
  ASSERT_EQ(rows.size(), 1u);
  const auto& row = rows[0];
  EXPECT_EQ(row["id"], "r1");
  EXPECT_EQ(row["video"], video);
  EXPECT_EQ(row["origin"], "track");
  EXPECT_EQ(row["param_names"].size(), tracker::parameter_infos().size());
  const auto names = row["param_names"].get<std::vector<std::string>>();
  const auto at = [&](const std::string& n) {
    return row["params"][std::find(names.begin(), names.end(), n) - names.begin()].get<double>();
  };
  EXPECT_EQ(at("ncc_min"), 0.5);
  EXPECT_EQ(at("n_lost"), 6);
  EXPECT_EQ(row["summary"]["frames"], 40);
  EXPECT_EQ(row["summary"]["fps"], 25.0);
  EXPECT_EQ(row["summary"]["has_truth"], true);
  EXPECT_TRUE(row["summary"]["accuracy"].is_object());
  EXPECT_GE(row["summary"]["track_share"].get<double>(), 0.0);
  EXPECT_LE(row["summary"]["track_share"].get<double>(), 1.0);

  const auto one = body(get("/api/v1/runs/r1"));
  EXPECT_EQ(one["summary"], row["summary"]);
  EXPECT_TRUE(one["header"].is_object());

  // The log in both encodings decodes to the same frames.
  const Response json_log = get("/api/v1/runs/r1/log");
  ASSERT_EQ(json_log.status, 200);
  EXPECT_EQ(json_log.content_type, "application/json");
  const Response bin_log = get("/api/v1/runs/r1/log", {{"format", "binary"}});
  ASSERT_EQ(bin_log.status, 200);
  EXPECT_EQ(bin_log.content_type, "application/x-protobuf");
  const tracker::TrackerLog a = tracker::decode_log(json_log.body), b = tracker::decode_log(bin_log.body);
  EXPECT_EQ(a.frames.size(), 40u);
  EXPECT_EQ(b.frames.size(), 40u);
  EXPECT_EQ(a.truth.size(), 40u);
  EXPECT_EQ(a.header.run_id, b.header.run_id);
  expect_detail(get("/api/v1/runs/r1/log", {{"format", "xml"}}), 400, "invalid_argument", "format",
                "format must be json or binary, got 'xml'");

  // Paged frame records.
  const auto page = body(get("/api/v1/runs/r1/frames", {{"from", "10"}, {"to", "15"}}));
  EXPECT_EQ(page["from"], 10);
  EXPECT_EQ(page["to"], 15);
  EXPECT_EQ(page["total"], 40);
  ASSERT_EQ(page["frames"].size(), 5u);
  EXPECT_EQ(page["frames"][0], tracker::frame_to_json(a.frames[10]));
  ASSERT_EQ(page["truth"].size(), 5u);
  EXPECT_EQ(page["truth"][0]["teats"].size(), 4u);
  EXPECT_EQ(body(get("/api/v1/runs/r1/frames"))["frames"].size(), 40u);  // default page: 100 frames
  expect_detail(get("/api/v1/runs/r1/frames", {{"from", "41"}}), 400, "invalid_argument", "from",
                "from must lie in 0..40, got 41");
  expect_detail(get("/api/v1/runs/r1/frames", {{"from", "5"}, {"to", "3"}}), 400, "invalid_argument", "to",
                "to must lie in 5..40, got 3");
  expect_detail(get("/api/v1/runs/r9/frames"), 404, "not_found", "run", "run 'r9' does not exist");
}

TEST_F(RunsTest, TrackParametersAreCheckedBeforeTheJob) {
  const std::string video = upload_video(5);
  const auto post = [&](const std::string& b) { return send("POST", "/api/v1/runs/track", b); };
  expect_error(post(R"({"video": ")" + video + R"(", "params": {"nope": 1}})"), 400, "invalid_argument",
               "nope");
  expect_error(post(R"({"video": ")" + video + R"(", "params": {"ncc_min": 2}})"), 400, "invalid_argument",
               "ncc_min");
  expect_detail(post(R"({"video": ")" + video + R"(", "params": {"ncc_min": "high"}})"), 400,
                "invalid_argument", "ncc_min", "ncc_min: must be a number");
  expect_detail(post(R"({"video": ")" + video + R"(", "params": {"z_min_mm": 950}})"), 400,
                "invalid_argument", "z_max_mm", "z_max_mm must exceed z_min_mm (950), got 900");
  expect_detail(post(R"({"params": {}})"), 400, "invalid_argument", "video", "video: required");
  expect_detail(post(R"({"video": ")" + video + R"(", "speed": 2})"), 400, "invalid_argument", "speed",
                "unknown field 'speed'");
  expect_detail(post(R"({"video": "v77"})"), 404, "not_found", "video", "video 'v77' does not exist");
  expect_detail(post("not json"), 400, "invalid_argument", "body", "body: must be a JSON object");
  EXPECT_TRUE(app->jobs.list().empty());
}

TEST_F(RunsTest, UploadLogsInBothEncodings) {
  const std::string video = upload_video(12);
  ASSERT_EQ(track(video), "r1");
  const std::string binary = get("/api/v1/runs/r1/log", {{"format", "binary"}}).body;
  const std::string json = get("/api/v1/runs/r1/log").body;

  const Response up = send("POST", "/api/v1/runs", binary);
  ASSERT_EQ(up.status, 201) << up.body;
  EXPECT_EQ(body(up)["id"], "r2");
  EXPECT_EQ(header(up, "Location"), "/api/v1/runs/r2");
  EXPECT_EQ(body(up)["origin"], "upload");
  EXPECT_EQ(body(up)["summary"], body(get("/api/v1/runs/r1"))["summary"]);

  const auto file = tmp.path() / "run.json";
  std::ofstream(file) << json;
  const Response up2 = upload("/api/v1/runs", file);  // streamed like a large upload
  ASSERT_EQ(up2.status, 201) << up2.body;
  EXPECT_EQ(body(up2)["id"], "r3");
  EXPECT_EQ(body(get("/api/v1/runs"))["runs"].size(), 3u);
  EXPECT_TRUE(std::filesystem::is_empty(store->upload_dir()));
}

TEST_F(RunsTest, BadUploadsAreRefusedWithTheDecodersMessage) {
  expect_detail(send("POST", "/api/v1/runs", "{ not json"), 415, "unsupported_format", "log",
                "log: not JSON text");
  expect_error(send("POST", "/api/v1/runs", std::string("\x0a\x05garbage-bytes\xff\xff", 17)), 415,
               "unsupported_format", "log");
  expect_error(send("POST", "/api/v1/runs", R"({"header": {"version": 99}})"), 400, "invalid_argument",
               "log");
  expect_error(send("POST", "/api/v1/runs", R"({"hedaer": {}})"), 400, "invalid_argument", "log");
  expect_detail(send("POST", "/api/v1/runs"), 400, "invalid_argument", "body", "body: the upload is empty");
  Request r;
  r.method = "POST", r.path = "/api/v1/runs";
  r.body_file = store->upload_dir() / "big-upload";
  { std::ofstream(r.body_file) << "x"; }
  std::filesystem::resize_file(r.body_file, limits::kMaxRunBytes + 1);
  expect_detail(router.handle(r), 413, "payload_too_large", "body",
                "run upload exceeds the limit of 256 MiB");
  EXPECT_FALSE(std::filesystem::exists(r.body_file));
  EXPECT_EQ(body(get("/api/v1/runs"))["runs"].size(), 0u);
}

TEST_F(RunsTest, DeleteAndReopen) {
  const std::string video = upload_video(6);
  ASSERT_EQ(track(video), "r1");
  ASSERT_EQ(track(video), "r2");
  EXPECT_EQ(send("DELETE", "/api/v1/runs/r1").status, 204);
  expect_detail(get("/api/v1/runs/r1"), 404, "not_found", "run", "run 'r1' does not exist");
  expect_detail(send("DELETE", "/api/v1/runs/r1"), 404, "not_found", "run", "run 'r1' does not exist");
  // An interrupted put (a log without its row) disappears at the next start.
  std::ofstream(tmp.path() / "store" / "runs" / "r7.tslog") << "half";
  open_empty();
  const auto rows = body(get("/api/v1/runs"))["runs"];
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0]["id"], "r2");
  EXPECT_EQ(get("/api/v1/runs/r2/frames").status, 200);
  EXPECT_FALSE(std::filesystem::exists(tmp.path() / "store" / "runs" / "r7.tslog"));
  EXPECT_EQ(track(video), "r3");
}

}  // namespace
}  // namespace trailscope::server
