// Segmentation on the synthetic ToF camera's `standard` frames (tof/synth.hpp): each visible teat tip's
// ground-truth projection should fall on (or within 3 px of) a peak segment of its own.
#if __has_include("trailscope/tof/synth.hpp")
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <set>

#include "trailscope/dmd/dmd.hpp"
#include "trailscope/tof/synth.hpp"

namespace trailscope::dmd {
namespace {

// The peak segment nearest to (u, v) within `radius` px, or 0.
int nearest_peak(const DmdResult& r, int width, int height, int u, int v, int radius) {
  int best = 0;
  int best_d2 = radius * radius + 1;
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx) {
      const int x = u + dx, y = v + dy, d2 = dx * dx + dy * dy;
      if (x < 0 || y < 0 || x >= width || y >= height || d2 >= best_d2) continue;
      const int label = r.labels[static_cast<std::size_t>(y) * width + x];
      if (r.segments[label - 1].kind != SegmentKind::peak) continue;
      best = label;
      best_d2 = d2;
    }
  return best;
}

TEST(SynthSegmentation, VisibleTeatTipsFallOnTheirOwnPeakSegments) {
  int visible = 0, matched = 0;
  for (const std::uint64_t seed : {1, 2, 3}) {
    tof::SynthOptions o;
    o.scenario = tof::Scenario::standard;
    o.seed = seed;
    o.frames = 250;
    const tof::ToFSynth synth(o);
    for (std::size_t f = 0; f < o.frames; f += 10) {
      const tof::DepthFrame frame = synth.render(f);
      const DepthImage depth{o.width, o.height, frame.depth_mm};
      const DepthRange range = valid_depth_range(depth);
      DmdParams p;
      p.layers = 32;  // ToF frames span a wide depth range: finer layers keep small distant teats apart
      p.min_gap = 3;
      const DmdResult r = run_dmd(depth_to_grey(depth, range.near_mm, range.far_mm), p);
      ASSERT_TRUE(frame.truth.has_value());
      std::set<int> used;
      for (const tof::TeatTruth& t : frame.truth->teats) {
        if (!t.visible || !t.tip_px) continue;
        const int u = static_cast<int>(std::lround((*t.tip_px)[0])),
                  v = static_cast<int>(std::lround((*t.tip_px)[1]));
        if (u < 0 || v < 0 || u >= o.width || v >= o.height) continue;
        ++visible;
        const int label = nearest_peak(r, o.width, o.height, u, v, 3);
        if (label > 0 && used.insert(label).second) ++matched;
      }
    }
  }
  std::printf("synthetic standard frames: %d of %d visible tips on a peak segment of their own\n", matched,
              visible);
  ASSERT_GT(visible, 250);
  EXPECT_GE(matched, 0.95 * visible);
}

}  // namespace
}  // namespace trailscope::dmd
#endif
