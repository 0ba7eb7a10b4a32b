// The real 16-bit depth frames in $TRAILSCOPE_SHARED/data/tracker (its manifest SOURCES.md) load as
// documented. The expected numbers are SOURCES.md's; the pixel values are checked against OpenImageIO
// read directly.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>

#include "test_support.hpp"
#include "trailscope/tof/depth_video_io.hpp"

namespace trailscope::tof {
namespace {
namespace fs = std::filesystem;

std::vector<std::uint16_t> raw_png(const fs::path& p) {
  auto in = OIIO::ImageInput::open(p.string());
  EXPECT_TRUE(in) << p;
  const auto& spec = in->spec();
  std::vector<std::uint16_t> px(static_cast<std::size_t>(spec.width) * spec.height);
  EXPECT_TRUE(in->read_image(0, 0, 0, 1, OIIO::TypeDesc::UINT16, px.data()));
  return px;
}

struct Stats {
  double zero_share = 0;
  float min = 0, max = 0;
};
Stats stats(const std::vector<float>& depth) {
  Stats s{0, 1e30f, -1e30f};
  std::size_t holes = 0;
  for (float z : depth) {
    if (std::isnan(z)) {
      ++holes;
      continue;
    }
    s.min = std::min(s.min, z);
    s.max = std::max(s.max, z);
  }
  s.zero_share = static_cast<double>(holes) / depth.size();
  return s;
}

TEST(RealFrames, Open3dRedwoodFolderLoads) {
  const fs::path dir = test::shared_data("tracker/depth_open3d_rgbd/depth");
  if (!fs::exists(dir)) GTEST_SKIP() << dir << " missing";
  const DepthVideo v = read_depth_video(dir);
  ASSERT_EQ(v.frames.size(), 5u);
  const Intrinsics& k = v.info.intrinsics;
  EXPECT_EQ(k.width, 640);
  EXPECT_EQ(k.height, 480);
  EXPECT_TRUE(k.defaulted);
  EXPECT_EQ(k.fx, 525.0);  // Open3D's PrimeSense default for these frames
  EXPECT_EQ(k.cx, 319.5);
  EXPECT_EQ(k.cy, 239.5);
  EXPECT_FALSE(v.info.has_amplitude);
  EXPECT_TRUE(v.info.timestamps_defaulted);
  EXPECT_DOUBLE_EQ(v.frames[4].timestamp_s, 4 / 30.0);
  EXPECT_EQ(v.info.source["files"][0], "00000.png");

  // SOURCES.md: frame 0 has 13.0% zeros (holes), valid depth 955 to 2702 mm.
  const Stats s = stats(v.frames[0].depth_mm);
  EXPECT_NEAR(s.zero_share, 0.130, 0.0005);
  EXPECT_EQ(s.min, 955.0f);
  EXPECT_EQ(s.max, 2702.0f);

  // Every pixel is the stored count in mm (0 -> NaN).
  for (int f = 0; f < 5; ++f) {
    char name[16];
    std::snprintf(name, sizeof name, "%05d.png", f);
    const auto raw = raw_png(dir / name);
    ASSERT_EQ(raw.size(), v.frames[f].depth_mm.size());
    std::size_t mismatches = 0;
    for (std::size_t i = 0; i < raw.size(); ++i) {
      const float z = v.frames[f].depth_mm[i];
      mismatches += raw[i] == 0 ? !std::isnan(z) : z != static_cast<float>(raw[i]);
    }
    EXPECT_EQ(mismatches, 0u) << name;
  }
}

TEST(RealFrames, TumFrameLoadsWithItsDepthUnit) {
  const fs::path file = test::shared_data("tracker/depth_open3d_rgbd/TUM_depth.png");
  if (!fs::exists(file)) GTEST_SKIP() << file << " missing";
  ImportOptions o;
  o.depth_unit_mm = 0.2;  // TUM RGB-D: 5000 counts per metre
  const DepthVideo v = read_depth_video(file, o);
  ASSERT_EQ(v.frames.size(), 1u);
  // SOURCES.md: 19.2% zero, raw values 7320 to 46655.
  const Stats s = stats(v.frames[0].depth_mm);
  EXPECT_NEAR(s.zero_share, 0.192, 0.0005);
  EXPECT_FLOAT_EQ(s.min, 7320 * 0.2f);
  EXPECT_FLOAT_EQ(s.max, 46655 * 0.2f);
}

}  // namespace
}  // namespace trailscope::tof
