// Flow-map tiles (render.hpp render_flow_tile): a tile is the same region of the whole-view render
// (render_flow, transparent background) byte for byte, tiles join without a seam, a zoom's tile matches
// its four children downsampled, and a grid across 180° is drawn on both sides of it.
#include <gtest/gtest.h>

#include <cmath>

#include "trailscope/core/error.hpp"
#include "trailscope/flow/render.hpp"
#include "trailscope/geo/tile_id.hpp"

namespace trailscope::flow {
namespace {

constexpr int kTile = 256;
constexpr int kZ = 7;  // the tiles compared with the whole view
constexpr double kUnits = double(std::int64_t{1} << 32) / (std::int64_t{1} << kZ) / kTile;  // per pixel
constexpr int kCellPx = 4;   // whole-view pixels per cell
constexpr int kCells = 128;  // 512 px: 2 × 2 tiles at kZ

/// Two vortices and a drift, as an uploaded field (proto/flow_field.md): lines that curve across the
/// middle of the grid, where the four tiles meet.
std::string two_vortices_json(int n) {
  nlohmann::json u = nlohmann::json::array(), v = nlohmann::json::array();
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = (i + 0.5) / n * 2 - 1, y = 1 - (j + 0.5) / n * 2;  // y up
      const double a = std::exp(-6 * ((x + 0.4) * (x + 0.4) + (y - 0.3) * (y - 0.3)));
      const double b = std::exp(-6 * ((x - 0.4) * (x - 0.4) + (y + 0.3) * (y + 0.3)));
      u.push_back(-(y - 0.3) * a + (y + 0.3) * b + 0.3), v.push_back((x + 0.4) * a - (x - 0.4) * b + 0.1);
    }
  return nlohmann::json{
      {"format", "trailscope-flow-field"}, {"version", 1}, {"width", n}, {"height", n}, {"u", u}, {"v", v}}
      .dump();
}

/// The flow map of the field on a geographic grid whose corner is the north-west corner of tile
/// (kZ, tx, ty) and whose cell is kCellPx tile pixels at kZ: the whole view's pixels are the tiles'.
FlowMap aligned_map(double x0, double y0) {
  VectorField f = parse_field(two_vortices_json(kCells));
  f.grid.geographic = true;
  f.grid.x0 = x0, f.grid.y0 = y0, f.grid.cell = kCellPx * kUnits;
  FlowParams p;
  p.lines.min_traffic = 0.01;
  p.lines.min_coherence = 0;
  return flow_map(std::move(f), p, Backend::cpu);
}

double origin(int tile) {
  return double(geo::tile_origin_x(geo::TileId{kZ, tile, 0}));
}

density::Image whole_view(const FlowMap& m, double level, double line_width = 1.5) {
  FlowRenderParams rp;
  rp.cell_px = kCellPx, rp.level = level, rp.line_width = line_width, rp.background = "transparent";
  density::Image base;
  base.width = base.height = kCells * kCellPx;
  base.rgba.assign(std::size_t(base.width) * base.height * 4, 0);
  return render_flow(m, base, rp);
}

density::Image tile(const FlowMap& m, geo::TileId t, double level, int size = kTile,
                    double line_width = 1.5) {
  FlowRenderParams rp;
  rp.level = level, rp.line_width = line_width;
  return render_flow_tile(m, t, size, rp);
}

/// Pixels [x0, x0 + w) × [y0, y0 + h) of `img`, as RGBA bytes.
std::vector<std::uint8_t> crop(const density::Image& img, int x0, int y0, int w, int h) {
  std::vector<std::uint8_t> out;
  for (int y = y0; y < y0 + h; ++y) out.insert(out.end(), img.pixel(x0, y), img.pixel(x0, y) + 4 * w);
  return out;
}

std::size_t opaque(const std::vector<std::uint8_t>& rgba) {
  std::size_t n = 0;
  for (std::size_t p = 3; p < rgba.size(); p += 4) n += rgba[p] > 0;
  return n;
}

TEST(FlowTiles, EachTileIsItsRegionOfTheWholeView) {
  const int tx = 64, ty = 40;  // the grid's corner: longitude 0, tile row 40
  const FlowMap m = aligned_map(origin(tx), origin(ty));
  ASSERT_GT(m.lines.size(), 20u);
  for (const double level : {0.5, 1.0, 1.5, 2.0}) {
    SCOPED_TRACE("level " + std::to_string(level));
    const density::Image whole = whole_view(m, level);
    ASSERT_EQ(whole.width, 2 * kTile);
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const density::Image t = tile(m, geo::TileId{kZ, tx + dx, ty + dy}, level);
        ASSERT_EQ(t.width, kTile);
        const auto want = crop(whole, dx * kTile, dy * kTile, kTile, kTile);
        EXPECT_GT(opaque(want), 1000u) << "tile " << dx << "," << dy << " has lines";
        EXPECT_EQ(t.rgba, want) << "tile " << dx << "," << dy;
      }
    // One 512 px tile a zoom up covers the same pixels.
    const density::Image big = tile(m, geo::TileId{kZ - 1, tx / 2, ty / 2}, level, 2 * kTile);
    EXPECT_EQ(big.rgba, whole.rgba);
  }
  // Lines cross the seams: the pixels on both sides of the middle column are drawn.
  const density::Image whole = whole_view(m, 2);
  std::size_t seam = 0;
  for (int y = 0; y < whole.height; ++y)
    seam += whole.pixel(kTile - 1, y)[3] > 0 && whole.pixel(kTile, y)[3] > 0;
  EXPECT_GT(seam, 10u);
  // Tiles the grid does not reach are transparent.
  for (const geo::TileId t :
       {geo::TileId{kZ, tx - 1, ty}, geo::TileId{kZ, tx + 2, ty + 1}, geo::TileId{kZ, tx, ty + 2}})
    EXPECT_EQ(opaque(tile(m, t, 2).rgba), 0u) << geo::to_string(t);
}

TEST(FlowTiles, FourChildrenDownsampledMatchTheirParent) {
  const FlowMap m = aligned_map(origin(64), origin(40));
  const geo::TileId parent{kZ - 1, 32, 20};
  // The children at twice the line width: the same lines in Mercator units, at twice the resolution.
  const auto kids = geo::children(parent);
  const density::Image p = tile(m, parent, 2, kTile, 1.5);
  std::vector<density::Image> kid_images;
  for (const auto& k : kids) kid_images.push_back(tile(m, k, 2, kTile, 3.0));
  double diff = 0, worst = 0;
  std::size_t drawn = 0;
  for (int y = 0; y < kTile; ++y)
    for (int x = 0; x < kTile; ++x) {
      // Premultiplied mean of the 2 × 2 child pixels under parent pixel (x, y).
      double acc[4] = {0, 0, 0, 0};
      for (int sy = 0; sy < 2; ++sy)
        for (int sx = 0; sx < 2; ++sx) {
          const int cx = 2 * x + sx, cy = 2 * y + sy;
          const density::Image& k = kid_images[(cy / kTile) * 2 + cx / kTile];
          const std::uint8_t* px = k.pixel(cx % kTile, cy % kTile);
          const double a = px[3] / 255.0;
          for (int c = 0; c < 3; ++c) acc[c] += px[c] / 255.0 * a / 4;
          acc[3] += a / 4;
        }
      const std::uint8_t* q = p.pixel(x, y);
      const double a = q[3] / 255.0;
      double d = std::abs(acc[3] - a);
      for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(acc[c] - q[c] / 255.0 * a));
      if (acc[3] > 0 || a > 0) ++drawn, diff += d;
      worst = std::max(worst, d);
    }
  ASSERT_GT(drawn, 5000u);
  // Antialiased coverage at two resolutions: equal on average, apart where a line's edge falls.
  // Measured: 0.017 and 0.41; the parent shifted by one pixel gives 0.16 and 0.90, children drawn at the
  // parent's line width 0.34 and 0.98.
  EXPECT_LT(diff / drawn, 0.04) << "mean premultiplied difference";
  EXPECT_LT(worst, 0.6);
}

TEST(FlowTiles, AGridAcross180IsDrawnOnBothSides) {
  // Corner in tile column 127 (the last): the grid's east half lies past 2^32, in column 0 of the world.
  const FlowMap m = aligned_map(origin(127), origin(40));
  const density::Image whole = whole_view(m, 2);
  EXPECT_EQ(tile(m, geo::TileId{kZ, 127, 40}, 2).rgba, crop(whole, 0, 0, kTile, kTile));
  EXPECT_EQ(tile(m, geo::TileId{kZ, 0, 40}, 2).rgba, crop(whole, kTile, 0, kTile, kTile));
  EXPECT_EQ(tile(m, geo::TileId{kZ, 0, 41}, 2).rgba, crop(whole, kTile, kTile, kTile, kTile));
  EXPECT_EQ(opaque(tile(m, geo::TileId{kZ, 1, 40}, 2).rgba), 0u);
}

TEST(FlowTiles, BadRequestsNameTheirParameter) {
  const FlowMap m = aligned_map(origin(64), origin(40));
  const auto param_of = [&](auto f) {
    try {
      f();
    } catch (const Error& e) {
      return e.param() + ":" + std::to_string(int(e.kind()));
    }
    return std::string("no error");
  };
  const auto invalid = std::to_string(int(Error::Kind::invalid_argument));
  EXPECT_EQ(param_of([&] { tile(m, geo::TileId{23, 0, 0}, 2); }), "z:" + invalid);
  EXPECT_EQ(param_of([&] { tile(m, geo::TileId{3, 8, 0}, 2); }), "x:" + invalid);
  EXPECT_EQ(param_of([&] { tile(m, geo::TileId{3, 0, 0}, 2, 300); }), "size:" + invalid);
  EXPECT_EQ(param_of([&] { tile(m, geo::TileId{3, 0, 0}, 2.5); }), "level:" + invalid);
  FlowMap plain = m;
  plain.field.grid.geographic = false;
  EXPECT_EQ(param_of([&] {
              tile(plain, geo::TileId{3, 0, 0}, 2);
            }),
            "grid:" + std::to_string(int(Error::Kind::unprocessable)));
}

}  // namespace
}  // namespace trailscope::flow
