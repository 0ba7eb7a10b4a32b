// Depth videos over the API, in process: pack uploads (good, garbage, not a pack, over the limit), the
// listing, description, frames and their pictures, synthetic videos as jobs, deletion and persistence.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "tracker_fixture.hpp"
#include "trailscope/density/png.hpp"

namespace trailscope::server {
namespace {

using VideosTest = test_routes::TrackerFixture;

TEST_F(VideosTest, UploadListGetDelete) {
  const Response r = upload("/api/v1/videos", make_pack("a", 30), {{"name", "cow one"}});
  ASSERT_EQ(r.status, 201) << r.body;
  const auto v = body(r);
  EXPECT_EQ(v["id"], "v1");
  EXPECT_EQ(header(r, "Location"), "/api/v1/videos/v1");
  EXPECT_EQ(v["name"], "cow one");
  EXPECT_EQ(v["origin"], "upload");
  EXPECT_EQ(v["frame_count"], 30);
  EXPECT_EQ(v["fps"], 25.0);
  EXPECT_EQ(v["has_truth"], true);
  EXPECT_EQ(v["intrinsics"]["width"], 176);
  EXPECT_EQ(v["format"], "trailscope-depth-video");
  EXPECT_GT(v["bytes"].get<std::uint64_t>(), 1000u);
  // One colour range for the video (the replay test checks it is the replay's): near the arm, far the
  // background, in mm.
  ASSERT_EQ(v["depth_range_mm"].size(), 2u);
  EXPECT_GT(v["depth_range_mm"][0].get<double>(), 0.0);
  EXPECT_GT(v["depth_range_mm"][1].get<double>() - v["depth_range_mm"][0].get<double>(), 100.0);
  EXPECT_EQ(body(get("/api/v1/videos"))["videos"].size(), 1u);
  EXPECT_EQ(body(get("/api/v1/videos/v1")), v);
  // The upload file became the store's; nothing is left in the upload folder.
  EXPECT_TRUE(std::filesystem::is_empty(store->upload_dir()));
  EXPECT_EQ(send("DELETE", "/api/v1/videos/v1").status, 204);
  expect_detail(get("/api/v1/videos/v1"), 404, "not_found", "video", "video 'v1' does not exist");
  expect_detail(send("DELETE", "/api/v1/videos/v1"), 404, "not_found", "video", "video 'v1' does not exist");
  EXPECT_EQ(body(get("/api/v1/videos"))["videos"].size(), 0u);
}

TEST_F(VideosTest, FramesAndPictures) {
  const std::string id = upload_video(12);
  const Response f = get("/api/v1/videos/" + id + "/frames/3");
  ASSERT_EQ(f.status, 200) << f.body;
  const auto j = body(f);
  EXPECT_EQ(j["index"], 3);
  EXPECT_DOUBLE_EQ(j["timestamp_s"].get<double>(), 3.0 / 25.0);
  ASSERT_EQ(j["truth"]["teats"].size(), 4u);
  EXPECT_EQ(j["truth"]["teats"][0]["name"], "FL");
  EXPECT_TRUE(j["truth"]["teats"][0].contains("tip_mm"));
  expect_detail(get("/api/v1/videos/" + id + "/frames/12"), 404, "not_found", "i",
                "video 'v1' has 12 frames (0..11); there is no frame 12");
  expect_detail(get("/api/v1/videos/" + id + "/frames/-1"), 400, "invalid_argument", "i",
                "i must lie in 0..1000000000, got -1");
  expect_detail(get("/api/v1/videos/" + id + "/frames/x/depth.png"), 400, "invalid_argument", "i",
                "i: 'x' is not an integer");
  expect_detail(get("/api/v1/videos/v9/frames/0"), 404, "not_found", "video", "video 'v9' does not exist");

  const Response d = get("/api/v1/videos/" + id + "/frames/5/depth.png");
  ASSERT_EQ(d.status, 200) << d.body;
  EXPECT_EQ(d.content_type, "image/png");
  const density::Image img = density::decode_png(d.body);
  EXPECT_EQ(img.width, 176);
  EXPECT_EQ(img.height, 144);
  // The default range is the frame's 2nd..98th percentile, so both ends of the map are used.
  int opaque = 0;
  for (std::size_t i = 3; i < img.rgba.size(); i += 4) opaque += img.rgba[i] == 255;
  EXPECT_GT(opaque, 176 * 144 / 2);
  const Response ranged = get("/api/v1/videos/" + id + "/frames/5/depth.png",
                              {{"min", "100"}, {"max", "900"}, {"colormap", "fire"}});
  ASSERT_EQ(ranged.status, 200) << ranged.body;
  EXPECT_NE(ranged.body, d.body);
  expect_detail(get("/api/v1/videos/" + id + "/frames/5/depth.png", {{"min", "500"}, {"max", "400"}}), 400,
                "invalid_argument", "max",
                "the depth range must have min < max (mm), got min 500.000000, max 400.000000");
  expect_detail(get("/api/v1/videos/" + id + "/frames/5/depth.png", {{"min", "near"}}), 400,
                "invalid_argument", "min", "min: 'near' is not a number");
  expect_error(get("/api/v1/videos/" + id + "/frames/5/depth.png", {{"colormap", "rainbow"}}), 400,
               "invalid_argument", "colormap");
  expect_detail(get("/api/v1/videos/" + id + "/frames/5/depth.png", {{"cmap", "fire"}}), 400,
                "invalid_argument", "cmap", "unknown query parameter 'cmap'");

  const Response a = get("/api/v1/videos/" + id + "/frames/5/amplitude.png");
  ASSERT_EQ(a.status, 200) << a.body;
  const density::Image amp = density::decode_png(a.body);
  EXPECT_EQ(amp.width, 176);
  EXPECT_EQ(amp.height, 144);
  EXPECT_EQ(amp.rgba[0], amp.rgba[1]);  // grey
}

TEST_F(VideosTest, GarbageUploadIsRefusedWithTheReadersMessage) {
  const auto garbage = tmp.path() / "garbage.tsdv";
  std::ofstream(garbage) << "this is not a depth video";
  const Response r = upload("/api/v1/videos", garbage);
  expect_error(r, 415, "unsupported_format", "video");
  const std::string detail = body(r)["detail"];
  EXPECT_NE(detail.find("the upload"), std::string::npos) << detail;  // not the server's temporary path
  EXPECT_EQ(detail.find("test-upload"), std::string::npos) << detail;
  EXPECT_TRUE(std::filesystem::is_empty(store->upload_dir()));
  EXPECT_EQ(body(get("/api/v1/videos"))["videos"].size(), 0u);
  expect_detail(send("POST", "/api/v1/videos"), 400, "invalid_argument", "body", "body: the upload is empty");
}

TEST_F(VideosTest, ADepthPngIsNotAPack) {
  tof::SynthOptions o;
  o.frames = 2;
  tof::write_synthetic_video(o, tmp.path() / "folder", {});
  const Response r = upload("/api/v1/videos", tmp.path() / "folder" / "depth" / "000000.png");
  expect_detail(
      r, 415, "unsupported_format", "body",
      "body: a video upload must be a depth-video pack (.tsdv, proto/depth_video.md); pack a video folder "
      "or PNG frames with `trailscope synth --pack` or DepthVideoWriter");
}

TEST_F(VideosTest, TruncatedPackIsRefused) {
  const auto pack = make_pack("t", 5);
  std::filesystem::resize_file(pack, std::filesystem::file_size(pack) - 10);
  const Response r = upload("/api/v1/videos", pack);
  EXPECT_EQ(r.status, 415) << r.body;
  EXPECT_EQ(body(get("/api/v1/videos"))["videos"].size(), 0u);
}

TEST_F(VideosTest, OversizedUpload) {
  Request r;
  r.method = "POST", r.path = "/api/v1/videos";
  r.body_file = store->upload_dir() / "big-upload";
  { std::ofstream(r.body_file) << "x"; }
  std::filesystem::resize_file(r.body_file, limits::kMaxVideoUploadBytes + 1);
  expect_detail(router.handle(r), 413, "payload_too_large", "body",
                "video upload exceeds the limit of 2 GiB");
}

TEST_F(VideosTest, SynthJob) {
  const Response r = send("POST", "/api/v1/videos/synth",
                          R"({"scenario": "cups-attached", "frames": 24, "seed": 7, "noise_free": true})");
  ASSERT_EQ(r.status, 202) << r.body;
  const auto j = body(r);
  EXPECT_EQ(j["job"]["kind"], "synth");
  EXPECT_EQ(j["video"], "v1");
  const JobState done = app->jobs.wait(j["job"]["id"]);
  ASSERT_EQ(done.state, "done") << done.to_json().dump();
  EXPECT_EQ(done.result["id"], "v1");
  EXPECT_EQ(done.result["name"], "cups-attached seed 7");
  EXPECT_EQ(done.result["origin"], "synthetic");
  EXPECT_EQ(done.result["frame_count"], 24);
  EXPECT_EQ(done.result["source"]["scenario"], "cups-attached");
  EXPECT_EQ(done.result["depth_range_mm"].size(), 2u);
  EXPECT_EQ(body(get("/api/v1/videos/v1"))["frame_count"], 24);

  expect_error(send("POST", "/api/v1/videos/synth", R"({"scenario": "rodeo"})"), 400, "invalid_argument",
               "scenario");
  expect_detail(send("POST", "/api/v1/videos/synth", R"({"frames": 3})"), 400, "invalid_argument", "scenario",
                "scenario: required");
  expect_detail(send("POST", "/api/v1/videos/synth", R"({"scenario": "standard", "colour": 1})"), 400,
                "invalid_argument", "colour", "unknown field 'colour'");
  expect_detail(send("POST", "/api/v1/videos/synth", R"({"scenario": "standard", "frames": -3})"), 400,
                "invalid_argument", "frames", "frames: must be a non-negative integer");
  expect_error(send("POST", "/api/v1/videos/synth", R"({"scenario": "standard", "frames": 0})"), 400,
               "invalid_argument", "frames");
  expect_error(send("POST", "/api/v1/videos/synth", R"({"scenario": "standard", "width": 4})"), 400,
               "invalid_argument", "width");
  expect_error(send("POST", "/api/v1/videos/synth", R"({"scenario": "standard", "frames": 100001})"), 413,
               "payload_too_large", "frames");
  expect_detail(send("POST", "/api/v1/videos/synth", "[1]"), 400, "invalid_argument", "body",
                "body: must be a JSON object");
  // Refused requests reserved nothing: the next video is v2.
  EXPECT_EQ(upload_video(3), "v2");
}

TEST_F(VideosTest, SynthJobCancelledLeavesNothing) {
  const Response r = send("POST", "/api/v1/videos/synth", R"({"scenario": "standard", "frames": 3000})");
  ASSERT_EQ(r.status, 202) << r.body;
  const std::string job = body(r)["job"]["id"];
  EXPECT_EQ(send("DELETE", "/api/v1/jobs/" + job).status, 200);
  EXPECT_EQ(app->jobs.wait(job).state, "cancelled");
  EXPECT_EQ(body(get("/api/v1/videos"))["videos"].size(), 0u);
  EXPECT_TRUE(std::filesystem::is_empty(tmp.path() / "store" / "tmp"));
}

TEST_F(VideosTest, SurvivesReopen) {
  const std::string id = upload_video(4);
  open_empty();
  EXPECT_EQ(body(get("/api/v1/videos/" + id))["frame_count"], 4);
  EXPECT_EQ(get("/api/v1/videos/" + id + "/frames/3/depth.png").status, 200);
  EXPECT_EQ(upload_video(2), "v2");  // ids are not reused
}

TEST_F(VideosTest, AtMostMaxStoredVideos) {
  for (std::size_t i = 0; i < limits::kMaxStoredVideos; ++i) app->videos->reserve();
  const std::string msg = "the server stores at most 100 videos (kMaxStoredVideos); delete one first";
  expect_detail(send("POST", "/api/v1/videos/synth", R"({"scenario": "standard", "frames": 2})"), 409,
                "conflict", "video", msg);
  expect_detail(upload("/api/v1/videos", make_pack("full", 2)), 409, "conflict", "video", msg);
  EXPECT_TRUE(std::filesystem::is_empty(store->upload_dir()));  // the refused upload is not kept
  app->videos->release("v1");
  EXPECT_EQ(upload_video(2), "v101");
}

TEST_F(VideosTest, GarbageQueryValuesNeverCrash) {
  const std::string id = upload_video(3);
  const std::vector<std::string> paths = {"/api/v1/videos/" + id + "/frames/1/depth.png",
                                          "/api/v1/videos/" + id + "/frames/2"};
  EXPECT_GT(expect_no_server_errors(paths, {"min", "max", "colormap", "x"},
                                    garbage_values({"fire", "1e9", "-1e9", "300"}), 40, 3, 11),
            0);
}

}  // namespace
}  // namespace trailscope::server
