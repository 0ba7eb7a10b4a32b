// DMD on the five real Redwood depth frames (shared/data/tracker/depth_open3d_rgbd, 640x480, 16-bit mm):
// the PNG facts recorded in SOURCES.md, and a reconstruction whose PSNR rises with the number of
// layers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "test_support.hpp"
#include "trailscope/dmd/dmd.hpp"
#include "trailscope/dmd/image_io.hpp"

namespace trailscope::dmd {
namespace {

std::filesystem::path frame(int k) {
  char name[32];
  std::snprintf(name, sizeof name, "0000%d.png", k);
  return trailscope::test::shared_data("tracker/depth_open3d_rgbd/depth") / name;
}

TEST(RealDepth, FrameZeroMatchesTheRecordedFacts) {
  const PngInput in = read_png_input(frame(0));
  ASSERT_EQ(in.bits, 16);
  EXPECT_EQ(in.depth.width, 640);
  EXPECT_EQ(in.depth.height, 480);
  const auto holes = std::count(in.depth.mm.begin(), in.depth.mm.end(), 0.f);
  EXPECT_NEAR(double(holes) / in.depth.mm.size(), 0.130, 0.0005);  // SOURCES.md: 13.0 % zero
  const DepthRange r = valid_depth_range(in.depth);
  EXPECT_EQ(r.near_mm, 955);  // SOURCES.md: valid range 955 to 2702 mm
  EXPECT_EQ(r.far_mm, 2702);
}

TEST(RealDepth, PsnrRisesWithTheNumberOfLayers) {
  for (int k = 0; k < 5; ++k) {
    const PngInput in = read_png_input(frame(k));
    ASSERT_EQ(in.bits, 16);
    const DepthRange range = valid_depth_range(in.depth);
    const GreyImage grey = depth_to_grey(in.depth, range.near_mm, range.far_mm);
    std::vector<double> psnrs;
    for (const int layers : {4, 8, 16, 32}) {
      DmdParams p;
      p.layers = layers;
      const DmdResult r = run_dmd(grey, p);
      psnrs.push_back(psnr(grey, r.reconstruction));
      std::printf("frame %d layers %2d (used %2zu): PSNR %.2f dB, skeleton %lld px, %.1f ms\n", k, layers,
                  r.levels.size(), psnrs.back(), static_cast<long long>(r.skeleton_pixels), r.times.total_ms);
    }
    for (std::size_t i = 1; i < psnrs.size(); ++i)
      EXPECT_GT(psnrs[i], psnrs[i - 1] + 0.5) << "frame " << k << ": PSNR should rise with the layers";
  }
}

}  // namespace
}  // namespace trailscope::dmd
