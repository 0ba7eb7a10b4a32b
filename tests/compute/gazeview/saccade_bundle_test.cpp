// Saccade bundling (gazeview/saccade_bundle.hpp): the bundle keeps each saccade's ends where they were, in
// stimulus px, and draws parallel saccades together.
#include <gtest/gtest.h>

#include <cmath>

#include "test_support.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/gaze/ingest.hpp"
#include "trailscope/gazeview/saccade_bundle.hpp"

using namespace trailscope;
using namespace trailscope::gazeview;
using trailscope::test::shared_data;

namespace {
Saccade sac(double x0, double y0, double x1, double y1) {
  Saccade s;
  s.x0 = x0, s.y0 = y0, s.x1 = x1, s.y1 = y1;
  return s;
}
bundling::BundleParams small_params() {
  bundling::BundleParams p;
  p.size = 256;
  p.iterations = 6;
  return p;
}
void expect_ends_kept(const bundling::Bundled& b, const std::vector<Saccade>& s, bool resampled) {
  ASSERT_EQ(b.lines.size(), s.size());
  const bundling::Polylines back = b.frame.from_pixels(b.lines);
  const double tol = 1e-3 * 1024 / 256;  // float32 rounding in bundle pixels, scaled to the stimulus
  for (std::size_t i = 0; i < s.size(); ++i) {
    const std::size_t a = back.begin(i), e = back.end(i) - 1;
    if (resampled) ASSERT_GT(e, a + 1) << "resampled: more than the 2 input points";
    EXPECT_NEAR(back.x[a], s[i].x0, tol);
    EXPECT_NEAR(back.y[a], s[i].y0, tol);
    EXPECT_NEAR(back.x[e], s[i].x1, tol);
    EXPECT_NEAR(back.y[e], s[i].y1, tol);
  }
}
}  // namespace

TEST(GazeSaccadeBundle, ParallelSaccadesMeetAndEndsStay) {
  // Ten horizontal saccades 4 px apart, 600 px long, on a 1024 x 768 stimulus.
  std::vector<Saccade> s;
  for (int k = 0; k < 10; ++k) s.push_back(sac(200, 300 + 4 * k, 800, 300 + 4 * k));
  const Stimulus st{1024, 768};
  const bundling::Bundled b = bundle_saccades(s, st, small_params(), Backend::cpu);
  expect_ends_kept(b, s, true);
  // The middle points draw together: their spread in y is smaller than the 36 px of the input.
  const bundling::Polylines back = b.frame.from_pixels(b.lines);
  double lo = 1e9, hi = -1e9;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const std::size_t mid = (back.begin(i) + back.end(i)) / 2;
    lo = std::min(lo, back.y[mid]), hi = std::max(hi, back.y[mid]);
  }
  EXPECT_LT(hi - lo, 36.0 / 2);
  EXPECT_GT(b.quality.ink_reduction, 0);
  // The frame maps the stimulus box onto the whole image width.
  EXPECT_DOUBLE_EQ(b.frame.to_px_x(1024), 256);
  EXPECT_DOUBLE_EQ(b.frame.to_px_x(0), 0);
}

TEST(GazeSaccadeBundle, LundSaccades) {
  gaze::GazeIngestOptions o;
  o.geometry = {1024, 768, 38, 30, 67};
  const gaze::GazeDataset ds =
      gaze::read_gaze_file(shared_data("gaze/andersson2017_lund/tsv/UL23_img_Europe.tsv").string(), o);
  const ViewEvents ev = view_events(ds, {}, {}, SIZE_MAX);
  ASSERT_GT(ev.saccades.size(), 5u);
  // Independent: each saccade starts at the sample at its t_start and ends at the sample at its t_end.
  const auto& r = ds.recordings[0];
  for (const Saccade& q : ev.saccades) {
    std::size_t a = 0;
    while (r.t_ms[a] != q.t_start_ms) ++a;
    std::size_t e = a;
    while (r.t_ms[e] != q.t_end_ms) ++e;
    EXPECT_EQ(q.x0, r.x[a]);
    EXPECT_EQ(q.y1, r.y[e]);
  }
  const bundling::Bundled b = bundle_saccades(ev.saccades, {1024, 768}, small_params(), Backend::cpu);
  expect_ends_kept(b, ev.saccades, false);  // short saccades (< spl) keep only their ends
}

TEST(GazeSaccadeBundle, NothingToBundle) {
  try {
    bundle_saccades({}, {1024, 768}, small_params(), Backend::cpu);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::unprocessable);
    EXPECT_EQ(e.param(), "stimulus");
    EXPECT_STREQ(e.what(), "no saccade to bundle in the selected recordings");
  }
}
