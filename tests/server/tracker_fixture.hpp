#pragma once
// The real router over an empty store with videos, runs and replays, and small synthetic depth videos,
// for the video, run and replay route tests.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "route_fixture.hpp"
#include "trailscope/tof/depth_video_io.hpp"
#include "trailscope/tof/synth.hpp"
#include "trailscope/tracker/params.hpp"
#include "trailscope/tracker/tracker_log.hpp"

namespace trailscope::server::test_routes {

class TrackerFixture : public RouteFixture {
 protected:
  TrackerFixture() { open_empty(); }
  /// Builds the app over an empty store in tmp/store (again: a reopen after a restart).
  void open_empty() {
    app.reset();
    store = std::make_shared<EmbeddedStore>(tmp.path() / "store");
    app = std::make_unique<App>(store, store->upload_dir(), std::filesystem::path(), limits::kTileCacheBytes,
                                tmp.path() / "store");
    router = make_router(*app);
  }
  /// Writes a synthetic pack (176x144, 25 fps) to tmp/<name>.tsdv and returns its path.
  std::filesystem::path make_pack(const std::string& name, std::size_t frames, std::uint64_t seed = 1,
                                  tof::Scenario scenario = tof::Scenario::standard) {
    tof::SynthOptions o;
    o.scenario = scenario, o.frames = frames, o.seed = seed;
    tof::WriteOptions w;
    w.layout = tof::VideoLayout::pack;
    const auto path = tmp.path() / (name + ".tsdv");
    tof::write_synthetic_video(o, path, w);
    return path;
  }
  /// POSTs the file at `path` as a streamed upload (a copy: the handler takes the file it is given).
  Response upload(const std::string& route, const std::filesystem::path& path,
                  std::map<std::string, std::string> query = {}) {
    Request r;
    r.method = "POST", r.path = route, r.query = std::move(query);
    r.principal = principal;
    static int n = 0;
    r.body_file = store->upload_dir() / ("test-upload-" + std::to_string(n++));
    std::filesystem::copy_file(path, r.body_file);
    return router.handle(r);
  }
  /// Uploads a synthetic pack of `frames` frames and returns the video id.
  std::string upload_video(std::size_t frames, std::uint64_t seed = 1) {
    static int n = 0;
    const Response r = upload("/api/v1/videos", make_pack("pack" + std::to_string(n++), frames, seed));
    EXPECT_EQ(r.status, 201) << r.body;
    return r.status == 201 ? body(r).at("id").get<std::string>() : "";
  }
  static void expect_detail(const Response& r, int status, const std::string& error, const std::string& param,
                            const std::string& detail) {
    expect_error(r, status, error, param);
    EXPECT_EQ(body(r)["detail"], detail);
  }
  /// Uploads a log of `frames` frames without ground truth, made with ncc_min = `ncc` and n_lost = `n_lost`
  /// (the other parameters at their defaults), whose first `track` frames are in TRACK and the rest in
  /// SEARCH: a run whose track share is known.
  void upload_state_log(double ncc, double n_lost, std::size_t track, std::size_t frames) {
    tracker::TrackerLog log;
    tracker::TrackerParams p;
    tracker::set_param(p, "ncc_min", ncc);
    tracker::set_param(p, "n_lost", n_lost);
    const auto values = tracker::to_vector(p);
    for (std::size_t i = 0; i < values.size(); ++i)
      log.header.params.push_back({tracker::parameter_infos()[i].name, values[i]});
    log.header.fps = 25;
    log.frames.resize(frames);
    for (std::size_t i = 0; i < frames; ++i) {
      log.frames[i].index = i;
      log.frames[i].timestamp_s = static_cast<double>(i) / 25.0;
      log.frames[i].state = i < track ? tracker::State::track : tracker::State::search;
    }
    log.header.frame_count = frames;
    const Response r = send("POST", "/api/v1/runs", tracker::encode_log(log, tracker::LogEncoding::binary));
    ASSERT_EQ(r.status, 201) << r.body;
  }
};

}  // namespace trailscope::server::test_routes
