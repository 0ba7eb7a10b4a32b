// Degenerate inputs: a single pixel, a constant image, fewer distinct values than layers.
#include <gtest/gtest.h>

#include "draw.hpp"
#include "trailscope/dmd/dmd.hpp"

namespace trailscope::dmd {
namespace {

TEST(DmdEdgeCases, ConstantImagesAreOneCanvasSegment) {
  for (const GreyImage& g : {GreyImage{1, 1, {7}}, test::blank_grey(13, 9, 200)}) {
    const DmdResult r = run_dmd(g);
    EXPECT_EQ(r.levels, std::vector<int>{g.pixels[0]});
    EXPECT_TRUE(r.layers.empty());
    EXPECT_EQ(r.reconstruction.pixels, g.pixels);
    ASSERT_EQ(r.segments.size(), 1u);
    EXPECT_EQ(r.segments[0].kind, SegmentKind::canvas);
    EXPECT_EQ(r.segments[0].area, g.width * g.height);
    EXPECT_EQ(r.segments[0].mean_value, g.pixels[0]);
  }
}

TEST(DmdEdgeCases, LayersAreCappedByDistinctValuesAndMinGap) {
  GreyImage g = test::blank_grey(20, 10, 0);
  for (int x = 0; x < 20; ++x)
    for (int y = 0; y < 10; ++y) g.pixels[y * 20 + x] = static_cast<std::uint8_t>(x * 3);  // 0, 3, ..., 57
  DmdParams p;
  p.layers = 40;
  p.min_gap = 1;
  EXPECT_EQ(run_dmd(g, p).levels.size(), 20u);
  p.min_gap = 6;  // every other value at most
  const DmdResult r = run_dmd(g, p);
  EXPECT_LE(r.levels.size(), 10u);
  for (std::size_t i = 1; i < r.levels.size(); ++i) EXPECT_GE(r.levels[i] - r.levels[i - 1], 6);
  p.selection = LayerSelection::local_maxima;
  const DmdResult m = run_dmd(g, p);
  for (std::size_t i = 1; i < m.levels.size(); ++i) EXPECT_GE(m.levels[i] - m.levels[i - 1], 6);
  EXPECT_EQ(m.levels.front(), 0);
}

}  // namespace
}  // namespace trailscope::dmd
