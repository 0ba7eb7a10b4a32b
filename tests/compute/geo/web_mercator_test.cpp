// Web Mercator against independent numbers: EPSG:3857 metres of the world's corners, the 32-bit fixed
// point of adsb.exposed at known points, and round trips.
#include "trailscope/geo/web_mercator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace trailscope::geo {
namespace {

TEST(WebMercator, MaxLatitudeIsWhereTheSquareWorldEnds) {
  // atan(sinh(π)) in degrees, the usual 85.0511287798° of EPSG:3857.
  EXPECT_NEAR(kMaxLatitude, 85.0511287798, 1e-10);
  EXPECT_NEAR(lat_to_unit_y(kMaxLatitude), 0.0, 1e-15);
  EXPECT_NEAR(lat_to_unit_y(-kMaxLatitude), 1.0, 1e-15);
  EXPECT_EQ(lat_to_merc_y(kMaxLatitude), 0u);
  EXPECT_DOUBLE_EQ(lat_to_unit_y(0.0), 0.5);
}

TEST(WebMercator, MetresMatchEpsg3857Bounds) {
  // EPSG:3857 projected bounds are ±20037508.342789244 m in both axes.
  EXPECT_NEAR(lon_to_meters_x(180.0), 20037508.342789244, 1e-6);
  EXPECT_NEAR(lat_to_meters_y(kMaxLatitude), 20037508.342789244, 1e-4);
  EXPECT_NEAR(lat_to_meters_y(-90.0), -20037508.342789244, 1e-4);  // clamped
  // Amsterdam Schiphol, 4.76°E 52.31°N: x = R·λ, y = R·ln tan(π/4 + φ/2).
  const double phi = 52.31 * M_PI / 180.0;
  EXPECT_NEAR(lat_to_meters_y(52.31), 6378137.0 * std::log(std::tan(M_PI / 4 + phi / 2)), 1e-6);
  EXPECT_NEAR(lon_to_meters_x(4.76), 6378137.0 * 4.76 * M_PI / 180.0, 1e-9);
}

TEST(WebMercator, FixedPointIsAdsbExposedConvention) {
  // x = 2^32·(lon+180)/360, y = 2^32·(½ − ln tan((lat+90)/360·π)/2π), truncated.
  EXPECT_EQ(lon_to_merc_x(-180.0), 0u);
  EXPECT_EQ(lon_to_merc_x(0.0), 1u << 31);
  EXPECT_EQ(lon_to_merc_x(90.0), 3u << 30);
  EXPECT_EQ(lon_to_merc_x(180.0), 0u);  // 180°E is 180°W
  EXPECT_EQ(lon_to_merc_x(179.99999999), 0xFFFFFFFFu);
  EXPECT_EQ(lat_to_merc_y(0.0), 1u << 31);
  EXPECT_EQ(lat_to_merc_y(89.0), 0u);
  EXPECT_EQ(lat_to_merc_y(-89.0), 0xFFFFFFFFu);
  for (double lat : {-60.0, -12.5, 33.3, 52.31, 71.0}) {
    const double expected =
        4294967296.0 * (0.5 - std::log(std::tan((lat + 90.0) / 360.0 * M_PI)) / (2 * M_PI));
    EXPECT_NEAR(static_cast<double>(lat_to_merc_y(lat)), std::floor(expected), 1.0) << lat;
  }
}

TEST(WebMercator, WrapsLongitudesAndClampsLatitudes) {
  EXPECT_DOUBLE_EQ(wrap_longitude(190.0), -170.0);
  EXPECT_DOUBLE_EQ(wrap_longitude(-190.0), 170.0);
  EXPECT_DOUBLE_EQ(wrap_longitude(540.0), -180.0);
  EXPECT_DOUBLE_EQ(wrap_longitude(12.25), 12.25);
  EXPECT_DOUBLE_EQ(clamp_latitude(89.0), kMaxLatitude);
  EXPECT_DOUBLE_EQ(clamp_latitude(-89.0), -kMaxLatitude);
  EXPECT_TRUE(std::isnan(clamp_latitude(NAN)));
}

TEST(WebMercator, RoundTrips) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> lon(-180.0, 180.0), lat(-85.0, 85.0);
  for (int i = 0; i < 1000; ++i) {
    const double a = lon(rng), b = lat(rng);
    EXPECT_NEAR(unit_x_to_lon(lon_to_unit_x(a)), a, 1e-9);
    EXPECT_NEAR(unit_y_to_lat(lat_to_unit_y(b)), b, 1e-9);
    // One 32-bit unit is 360/2^32 degrees of longitude; truncation loses less than that.
    EXPECT_NEAR(merc_x_to_lon(lon_to_merc_x(a)), a, 360.0 / 4294967296.0);
    EXPECT_LE(merc_x_to_lon(lon_to_merc_x(a)), a);
    EXPECT_NEAR(merc_y_to_lat(lat_to_merc_y(b)), b, 1e-7);
  }
}

}  // namespace
}  // namespace trailscope::geo
