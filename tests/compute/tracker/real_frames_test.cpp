// The teat tracker on real depth frames that show no cow: the five Redwood frames (Open3D's sample RGB-D
// images: a room at 1-3 m, 640x480, PrimeSense structured light, 13 % holes) and the TUM RGB-D frame. The
// tracker must report no teat in any frame, and never TRACK. With the default depth gate (80-900 mm, the
// working range under an udder) the whole scene is gated out; with the gate widened to cover the scene the
// detector and the 3D verification really run on it, and the four-teat udder model is what turns down the
// teat-like ends they find (edges and corners of furniture).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "test_support.hpp"
#include "trailscope/tof/depth_video_io.hpp"
#include "trailscope/tracker/tracker.hpp"

namespace trailscope::tracker {
namespace {

namespace fs = std::filesystem;

struct Seen {
  std::size_t frames = 0, valid_pixels = 0, verified = 0, teats = 0, tracked = 0;
};

Seen track(const fs::path& path, const tof::ImportOptions& import, const TrackerParams& params) {
  tof::DepthVideoReader reader(path, import);
  Tracker tracker(params, reader.info().intrinsics);
  Seen s;
  for (std::size_t i = 0; i < reader.size(); ++i) {
    const FrameLog log = tracker.process(reader.read_frame(i));
    ++s.frames;
    s.valid_pixels += static_cast<std::size_t>(log.valid_pixels);
    s.verified += static_cast<std::size_t>(log.verified);
    s.tracked += log.state == State::track;
    for (const TeatEstimate& t : log.teats) s.teats += t.visible;
  }
  return s;
}

TEST(TrackerOnRealFrames, RedwoodRoomShowsNoTeat) {
  const fs::path dir = test::shared_data("tracker/depth_open3d_rgbd/depth");
  if (!fs::exists(dir)) GTEST_SKIP() << dir << " missing";
  // The default gate: no pixel of the room (955-2702 mm) is within 80-900 mm.
  const Seen gated = track(dir, {}, TrackerParams{});
  EXPECT_EQ(gated.frames, 5u);
  EXPECT_EQ(gated.valid_pixels, 0u);
  EXPECT_EQ(gated.teats, 0u);
  EXPECT_EQ(gated.tracked, 0u);

  // The gate over the whole room: the detector sees every valid pixel, finds teat-like ends, and the udder
  // model accepts none of them.
  TrackerParams wide;
  wide.z_max_mm = 3000;
  const Seen open = track(dir, {}, wide);
  std::printf("Redwood, gate 80-3000 mm: %zu valid pixels, %zu verified candidates in %zu frames\n",
              open.valid_pixels, open.verified, open.frames);
  EXPECT_GT(open.valid_pixels, 5u * 640 * 480 / 2);  // most of the frame (13 % holes) passes the gate
  EXPECT_GT(open.verified, 0u);                      // so the verification really ran on the room
  EXPECT_EQ(open.teats, 0u);
  EXPECT_EQ(open.tracked, 0u);
}

TEST(TrackerOnRealFrames, TumFrameShowsNoTeat) {
  const fs::path file = test::shared_data("tracker/depth_open3d_rgbd/TUM_depth.png");
  if (!fs::exists(file)) GTEST_SKIP() << file << " missing";
  tof::ImportOptions import;
  import.depth_unit_mm = 0.2;  // TUM RGB-D: 5000 counts per metre
  TrackerParams wide;
  wide.z_max_mm = 10000;  // the parameter's upper bound; the frame reaches 9.3 m
  const Seen s = track(file, import, wide);
  EXPECT_EQ(s.frames, 1u);
  EXPECT_GT(s.valid_pixels, 640u * 480 / 2);
  EXPECT_EQ(s.teats, 0u);
  EXPECT_EQ(s.tracked, 0u);
}

}  // namespace
}  // namespace trailscope::tracker
