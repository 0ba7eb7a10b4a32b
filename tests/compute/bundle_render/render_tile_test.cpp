// XYZ tiles of a bundle in Web Mercator units: two neighbouring tiles must be exactly the two halves of
// one render of both (with the same margin), in every style, so a tiled map has no seams.
#include <gtest/gtest.h>

#include <random>

#include "render_test_util.hpp"
#include "test_support.hpp"
#include "trailscope/bundling/flight_trails.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/ingest/ingest.hpp"

namespace trailscope::bundling {
namespace {

constexpr std::int64_t kTile5 = std::int64_t{1} << 27;  // units of a zoom-5 tile

/// Random polylines over a view of zoom-5 tiles x 16..17, y 10 (plus half a tile around), many of them
/// crossing the seam between the two tiles.
Bundled mercator_bundle() {
  const double x0 = 16.0 * kTile5 - kTile5 / 2, x1 = 18.0 * kTile5 + kTile5 / 2;
  const double y0 = 10.0 * kTile5 - kTile5 / 2, y1 = 11.0 * kTile5 + kTile5 / 2;
  const Frame f = Frame::view(x0, y0, x1, y1, 512);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> ux(0, 512), uy(f.offset_y, 512 - f.offset_y);
  Polylines l;
  for (int k = 0; k < 150; ++k) {
    std::vector<double> xs{ux(rng)}, ys{uy(rng)};
    for (int s = 0; s < 4; ++s)
      xs.push_back(xs.back() + (ux(rng) - 256) / 3), ys.push_back(ys.back() + (uy(rng) - 256) / 5);
    l.add(xs, ys);
  }
  for (int k = 0; k < 30; ++k) test::add_straight(l, 150, 200 + k * 0.3, 360, 210 + k * 0.2, 7);  // a bundle
  Bundled b = test::make_bundled(l, 512);
  b.frame = f;
  return b;
}

density::Image crop(const density::Image& img, int x, int y, int w, int h) {
  density::Image out;
  out.width = w, out.height = h;
  for (int r = 0; r < h; ++r) {
    const std::uint8_t* row = img.pixel(x, y + r);
    out.rgba.insert(out.rgba.end(), row, row + 4 * static_cast<std::size_t>(w));
  }
  return out;
}

TEST(RenderTile, NeighbouringTilesAreTheHalvesOfOneRender) {
  const Bundled b = mercator_bundle();
  const int T = 256;
  for (Style style : {Style::lines, Style::shaded, Style::tube}) {
    for (ColorBy color : {ColorBy::length, ColorBy::density}) {
      SCOPED_TRACE(std::string(to_string(style)) + " " + to_string(color));
      RenderParams p;
      p.style = style;
      p.color = color;
      p.alpha_by_density = color == ColorBy::density;
      const int m = tile_margin_px(p);
      const density::Image left = render_bundle_tile(b, p, 5, 16, 10, T);
      const density::Image right = render_bundle_tile(b, p, 5, 17, 10, T);
      const density::Image both = render_bundle(b, p, tile_viewport(b, 5, 16, 10, T, 2, 1, m));
      ASSERT_EQ(both.width, 2 * T + 2 * m);
      ASSERT_EQ(left.width, T);
      EXPECT_EQ(left.rgba, crop(both, m, m, T, T).rgba);
      EXPECT_EQ(right.rgba, crop(both, m + T, m, T, T).rgba);
      // The seam is crossed: both edge columns have drawn pixels.
      int lit = 0;
      for (int y = 0; y < T; ++y)
        lit += (left.pixel(T - 1, y)[0] | left.pixel(T - 1, y)[1] | left.pixel(T - 1, y)[2]) != 0;
      EXPECT_GT(lit, 3);
    }
  }
}

TEST(RenderTile, ATileIsItsPartOfTheWholeImage) {
  // Far from the tile's edges (beyond the margin's reach) a tile equals the same area of a larger render.
  const Bundled b = mercator_bundle();
  RenderParams p;
  p.style = Style::lines;
  const density::Image tile = render_bundle_tile(b, p, 5, 16, 10, 256);
  const density::Image big = render_bundle(b, p, tile_viewport(b, 5, 16, 10, 256, 2, 2, 40));
  EXPECT_EQ(tile.rgba, crop(big, 40, 40, 256, 256).rgba);
}

TEST(RenderTile, EuropeFlightBundleTilesAreSeamless) {
  // The whole chain on real trails: an hour of the Europe SO6 day, bundled by the reference, cut into the
  // four zoom-4 tiles 7..8 × 4..5 (20°W–22.5°E, 41–67°N); the frame's scale is no power of two here.
  const auto path = trailscope::test::shared_data("flights/traffic_europe_20180101_m3.so6.gz");
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared data absent";
  const TrailSet ts = ingest::ingest_file(path.string());
  Query q;
  q.bbox = BBox{-10, 36, 30, 60};
  q.t0 = 1514764800.0 + 9 * 3600;
  q.t1 = 1514764800.0 + 10 * 3600;
  const FlightTrails ft = flight_trails(ts, q, 512, INFINITY);
  const Bundled b = bundle_ref(ft.frame.to_pixels(ft.lines), ft.frame, BundleParams{});
  RenderParams p;  // shaded, length
  const int T = 256, m = tile_margin_px(p);
  const density::Image block = render_bundle(b, p, tile_viewport(b, 4, 7, 4, T, 2, 2, m));
  std::size_t drawn = 0;
  for (int dx = 0; dx < 2; ++dx)
    for (int dy = 0; dy < 2; ++dy) {
      const density::Image tile = render_bundle_tile(b, p, 4, 7 + dx, 4 + dy, T);
      EXPECT_EQ(tile.rgba, crop(block, m + dx * T, m + dy * T, T, T).rgba) << dx << "," << dy;
      for (std::size_t i = 0; i < tile.rgba.size(); i += 4)
        drawn += tile.rgba[i] | tile.rgba[i + 1] | tile.rgba[i + 2];
    }
  EXPECT_GT(drawn, 0u);
}

TEST(RenderTile, BadTilesAndFramesAreRefusedByName) {
  Bundled b = mercator_bundle();
  RenderParams p;
  auto param_of = [&](auto&& f) {
    try {
      f();
    } catch (const Error& e) {
      return e.param();
    }
    return std::string("none");
  };
  EXPECT_EQ(param_of([&] { render_bundle_tile(b, p, 23, 0, 0, 256); }), "z");
  EXPECT_EQ(param_of([&] { render_bundle_tile(b, p, 5, 32, 0, 256); }), "x");
  EXPECT_EQ(param_of([&] { render_bundle_tile(b, p, 5, 0, 0, 8); }), "tile_size");
  b.frame.flip_y = true;
  EXPECT_EQ(param_of([&] { render_bundle_tile(b, p, 5, 16, 10, 256); }), "frame");
}

}  // namespace
}  // namespace trailscope::bundling
