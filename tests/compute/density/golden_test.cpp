// Golden images: whole-pipeline renderings compared with PNGs in tests/golden/ (see its README.md for
// how each was produced). Rendering is deterministic, so the images should match exactly; the tolerance
// (2/255 per channel, on all but 0.1 % of the pixels) only absorbs platform differences in floating-point
// shading (eq_hist interpolation, KDE sums). Set TRAILSCOPE_UPDATE_GOLDEN=1 to rewrite them.
#include <gtest/gtest.h>

#include "golden.hpp"

#include <cmath>
#include <cstdlib>

#include "density_test_util.hpp"

namespace trailscope::density {
namespace {

using test::compare_with_golden;

TEST(Golden, EuropeDayTile) {
  const TrailSet* eu = test::europe();
  if (!eu) GTEST_SKIP() << "shared data absent";
  DensityRenderer renderer;
  TileRequest r;  // defaults: 256 px, count, eq_hist, fire, no smoothing, 1800 s gap limit
  r.tile = geo::TileId{3, 4, 2};
  r.backend = Backend::cpu;
  compare_with_golden(decode_png(renderer.render_tile(*eu, "eu", Query{}, r).png),
                      "europe_3_4_2_count_fire.png");
}

TEST(Golden, EuropeDayAltitudeSmoothed) {
  const TrailSet* eu = test::europe();
  if (!eu) GTEST_SKIP() << "shared data absent";
  DensityRenderer renderer;
  TileRequest r;
  r.tile = geo::TileId{4, 8, 5};
  r.value = DensityValue::altitude;
  r.how = How::linear;
  r.cmap = "viridis";
  r.kernel_radius = 4;
  r.max_gap_seconds = INFINITY;
  r.backend = Backend::cpu;
  compare_with_golden(decode_png(renderer.render_tile(*eu, "eu", Query{}, r).png),
                      "europe_4_8_5_altitude_viridis_kde4.png");
}

TEST(Golden, SyntheticBoundingBox) {
  RenderOptions o;
  o.aggregate.backend = Backend::cpu;
  o.shade.how = How::log;
  o.shade.cmap = "magma";
  compare_with_golden(
      render_canvas(test::synthetic(), Query{}, Canvas::for_bbox(geo::LonLatBox{-10, 35, 25, 58}, 360), o),
      "synthetic_bbox_log_magma.png");
}

}  // namespace
}  // namespace trailscope::density
