// XYZ tile maths against OSM conventions (y = 0 north, points on an edge belong east/south) and
// round trips; errors name the parameter.
#include "trailscope/geo/tile_id.hpp"

#include <gtest/gtest.h>

#include <random>

#include "trailscope/core/error.hpp"
#include "trailscope/geo/web_mercator.hpp"

namespace trailscope::geo {
namespace {

std::string param_of(const TileId& t) {
  try {
    validate_tile(t);
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::invalid_argument);
    return e.param();
  }
  return "";
}

TEST(TileId, KnownTiles) {
  // Schiphol (4.76°E, 52.31°N) at zoom 10 is OSM tile 10/525/336: x = ⌊184.76/360·1024⌋ = 525,
  // y = ⌊(1 − asinh(tan 52.31°)/π)/2·1024⌋ = ⌊336.87⌋ = 336.
  EXPECT_EQ(tile_for_lonlat(4.76, 52.31, 10), (TileId{10, 525, 336}));
  EXPECT_EQ(tile_for_lonlat(0.0, 0.0, 0), (TileId{0, 0, 0}));
  // (0°, 0°) is the corner of the four zoom-1 tiles; on an edge the tile east and south wins.
  EXPECT_EQ(tile_for_lonlat(0.0, 0.0, 1), (TileId{1, 1, 1}));
  EXPECT_EQ(tile_for_lonlat(-0.001, 0.001, 1), (TileId{1, 0, 0}));
  // Sydney (151.21°E, 33.87°S) at zoom 5: x = ⌊331.21/360·32⌋ = 29, y = ⌊19.2⌋ = 19.
  EXPECT_EQ(tile_for_lonlat(151.21, -33.87, 5), (TileId{5, 29, 19}));
  EXPECT_EQ(to_string(TileId{10, 525, 336}), "10/525/336");
}

TEST(TileId, LatitudesBeyondTheSquareWorldClampToTheEdgeRows) {
  EXPECT_EQ(tile_for_lonlat(10.0, 89.9, 4).y, 0);
  EXPECT_EQ(tile_for_lonlat(10.0, -89.9, 4).y, 15);
  EXPECT_EQ(tile_for_lonlat(10.0, -kMaxLatitude, 4).y, 15);  // the south edge belongs to the last row
  EXPECT_EQ(tile_for_lonlat(190.0, 0.0, 2).x, 0);            // 190°E wraps to 170°W
}

TEST(TileId, BoundsFollowOsm) {
  const LonLatBox b = tile_bounds(TileId{1, 0, 0});
  EXPECT_DOUBLE_EQ(b.west, -180.0);
  EXPECT_DOUBLE_EQ(b.east, 0.0);
  EXPECT_NEAR(b.north, kMaxLatitude, 1e-12);
  EXPECT_NEAR(b.south, 0.0, 1e-12);
  const LonLatBox s = tile_bounds(TileId{10, 525, 336});
  EXPECT_LT(s.west, 4.76);
  EXPECT_GT(s.east, 4.76);
  EXPECT_LT(s.south, 52.31);
  EXPECT_GT(s.north, 52.31);
  EXPECT_NEAR(s.east - s.west, 360.0 / 1024, 1e-12);
}

TEST(TileId, BoundsRoundTrip) {
  std::mt19937 rng(11);
  for (int i = 0; i < 2000; ++i) {
    const int z = static_cast<int>(rng() % 23);
    const int n = 1 << z;
    const TileId t{z, static_cast<int>(rng() % n), static_cast<int>(rng() % n)};
    const LonLatBox b = tile_bounds(t);
    EXPECT_EQ(tile_for_lonlat((b.west + b.east) / 2, (b.south + b.north) / 2, z), t);
    // Just inside the north-west corner (the corner itself is one rounding away from the neighbours).
    const double in = 1e-6 * (b.east - b.west);
    EXPECT_EQ(tile_for_lonlat(b.west + in, b.north - in, z), t) << to_string(t);
    // Fixed-point origin and size agree with the degrees.
    EXPECT_NEAR(merc_x_to_lon(static_cast<double>(tile_origin_x(t))), b.west, 1e-9);
    EXPECT_NEAR(merc_y_to_lat(static_cast<double>(tile_origin_y(t))), b.north, 1e-9);
  }
}

TEST(TileId, ParentAndChildren) {
  const TileId t{10, 525, 336};
  EXPECT_EQ(parent(t), (TileId{9, 262, 168}));
  const auto c = children(t);
  EXPECT_EQ(c[0], (TileId{11, 1050, 672}));
  EXPECT_EQ(c[3], (TileId{11, 1051, 673}));
  for (const TileId& k : c) EXPECT_EQ(parent(k), t);
  EXPECT_EQ(tile_size_units(0), std::int64_t{1} << 32);
  EXPECT_EQ(tile_origin_x(TileId{1, 1, 0}), std::int64_t{1} << 31);
}

TEST(TileId, ErrorsNameTheParameter) {
  EXPECT_EQ(param_of(TileId{23, 0, 0}), "z");
  EXPECT_EQ(param_of(TileId{-1, 0, 0}), "z");
  EXPECT_EQ(param_of(TileId{3, 8, 0}), "x");
  EXPECT_EQ(param_of(TileId{3, -1, 0}), "x");
  EXPECT_EQ(param_of(TileId{3, 0, 8}), "y");
  EXPECT_EQ(param_of(TileId{22, (1 << 22) - 1, (1 << 22) - 1}), "");
  EXPECT_THROW(tile_for_lonlat(0, 0, 23), Error);
  EXPECT_THROW(parent(TileId{0, 0, 0}), Error);
  EXPECT_THROW(children(TileId{22, 0, 0}), Error);
}

}  // namespace
}  // namespace trailscope::geo
