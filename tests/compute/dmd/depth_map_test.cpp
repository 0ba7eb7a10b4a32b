// depth_to_grey: near is bright, holes and beyond-far are black, a linear map in between.
#include <gtest/gtest.h>

#include <cmath>

#include "trailscope/dmd/image.hpp"

namespace trailscope::dmd {
namespace {

TEST(DepthToGrey, MapsNearBrightFarDarkHolesBlack) {
  const DepthImage d{8, 1, {std::nanf(""), 0.f, -5.f, 400.f, 500.f, 750.f, 1000.f, 1001.f}};
  const GreyImage g = depth_to_grey(d, 500, 1000);
  ASSERT_EQ(g.width, 8);
  EXPECT_EQ(g.pixels, (std::vector<std::uint8_t>{0, 0, 0, 255, 255, 128, 1, 0}));
  const DepthRange r = valid_depth_range(d);
  EXPECT_EQ(r.near_mm, 400);
  EXPECT_EQ(r.far_mm, 1001);
}

TEST(DepthToGrey, IsMonotoneDecreasingInDepth) {
  DepthImage d{1000, 1, {}};
  for (int i = 0; i < 1000; ++i) d.mm.push_back(600.f + i * 0.5f);
  const GreyImage g = depth_to_grey(d, 600, 1099.5);
  for (int i = 1; i < 1000; ++i) EXPECT_LE(g.pixels[i], g.pixels[i - 1]);
  EXPECT_EQ(g.pixels.front(), 255);
  EXPECT_EQ(g.pixels.back(), 1);
}

TEST(Psnr, MatchesTheDefinition) {
  const GreyImage a{2, 2, {0, 0, 0, 0}}, b{2, 2, {0, 0, 0, 10}};
  EXPECT_NEAR(psnr(a, b), 10 * std::log10(255.0 * 255.0 / 25.0), 1e-9);
  EXPECT_TRUE(std::isinf(psnr(a, a)));
}

}  // namespace
}  // namespace trailscope::dmd
