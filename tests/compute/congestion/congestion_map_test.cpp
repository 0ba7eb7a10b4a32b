// The congestion map against computations written here: the time-weighted window by brute-force time
// integration (positions_at every 10 ms, each position put on the grid by the Mercator formula rather
// than the grid's edge parallels), the instant counts of the real Europe SO6 day by binning positions_at
// the same way, and the shading against the colormap.
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "test_support.hpp"
#include "trailscope/congestion/congestion_map.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/density/colormap.hpp"
#include "trailscope/density/png.hpp"
#include "trailscope/geo/web_mercator.hpp"
#include "trailscope/ingest/ingest.hpp"
#include "trailscope/trails/positions.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::congestion {
namespace {

constexpr double kT = 1514764800.0;

struct Fix {
  double t;
  float lat, lon, alt;
};

TrailSet make(const std::vector<std::vector<Fix>>& flights) {
  TrailSetBuilder b;
  int n = 0;
  for (const auto& fixes : flights) {
    char icao[7];
    std::snprintf(icao, sizeof icao, "%06x", 0x3c0000 + n);
    const std::string cs = "TST" + std::to_string(n++);
    for (const Fix& f : fixes) {
      Sample s;
      s.t = f.t, s.lat = f.lat, s.lon = f.lon, s.alt = f.alt;
      b.add(icao, cs, s);
    }
  }
  return b.build();
}

// The pixel of a position on a canvas by the Mercator formula in units (-1 outside).
long pixel_of(const density::Canvas& c, double lat, double lon) {
  if (std::fabs(lat) > geo::kMaxLatitude) return -1;
  const double p = static_cast<double>(c.pixel_units());
  const double y = geo::lat_to_unit_y(lat) * 4294967296.0;
  for (int k = -1; k <= 1; ++k) {
    const double x = (lon + 180.0 + 360.0 * k) / 360.0 * 4294967296.0;
    const double i = std::floor((x - static_cast<double>(c.origin_x())) / p);
    const double j = std::floor((y - static_cast<double>(c.origin_y())) / p);
    if (i >= 0 && i < c.width() && j >= 0 && j < c.height())
      return static_cast<long>(j) * c.width() + static_cast<long>(i);
  }
  return -1;
}

Query window(double t0, double t1) {
  Query q;
  q.t0 = t0, q.t1 = t1;
  return q;
}

// Zoom 8 tile holding (50°N, 5°E): 256 px of ~0.0055° (~390 m of latitude there).
const geo::TileId kTile = geo::tile_for_lonlat(5.0, 50.0, 8);

TrailSet traffic() {
  const auto box = geo::tile_bounds(kTile);
  const float w = static_cast<float>(box.west), e = static_cast<float>(box.east);
  const float s = static_cast<float>(box.south), n = static_cast<float>(box.north);
  const float cx = (w + e) / 2, cy = (s + n) / 2;
  return make({
      // Diagonal across the whole tile and beyond, one segment.
      {{kT - 100, s - 0.2f, w - 0.3f, 9000}, {kT + 700, n + 0.2f, e + 0.3f, 9000}},
      // A turn inside the tile (three samples), climbing.
      {{kT, n - 0.05f, w + 0.1f, 3000}, {kT + 200, cy, cx, 5000}, {kT + 500, s + 0.05f, cx - 0.3f, 8000}},
      // East-west along a parallel, starting inside.
      {{kT + 100, cy + 0.01f, cx, 10000}, {kT + 900, cy + 0.01f, e + 1.0f, 10000}},
      // Hovering: the same position at both ends.
      {{kT + 50, cy - 0.1f, cx + 0.1f, 500}, {kT + 400, cy - 0.1f, cx + 0.1f, 500}},
      // Outside the tile entirely.
      {{kT, n + 1.0f, w, 9000}, {kT + 600, n + 1.0f, e, 9000}},
  });
}

// Brute force: Σ over 10 ms steps (midpoints) of the flights' positions_at, per pixel, in seconds.
std::vector<double> brute_seconds(const TrailSet& set, const Query& filters, const density::Canvas& c,
                                  double t0, double t1, double dt) {
  std::vector<double> s(static_cast<std::size_t>(c.width()) * c.height(), 0.0);
  for (double t = t0 + dt / 2; t < t1; t += dt)
    for (const Position& p : positions_at(set, t, filters, 1000).positions) {
      const long px = pixel_of(c, p.lat, p.lon);
      if (px >= 0) s[static_cast<std::size_t>(px)] += dt;
    }
  return s;
}

void expect_window_matches(const TrailSet& set, const Query& filters, double t0, double t1) {
  const density::Canvas c = density::Canvas::for_tile(kTile, 256);
  Query q = filters;
  q.t0 = t0, q.t1 = t1;
  const density::Raster r = aircraft_per_pixel(set, q, c, std::nullopt);
  ASSERT_EQ(r.width, 256);
  const double dt = 0.01;
  const std::vector<double> brute = brute_seconds(set, filters, c, t0, t1, dt);
  double total_exact = 0, total_brute = 0;
  std::size_t pixels = 0;
  for (std::size_t i = 0; i < brute.size(); ++i) {
    const double exact = std::isnan(r.values[i]) ? 0.0 : r.values[i] * (t1 - t0);
    total_exact += exact, total_brute += brute[i];
    pixels += exact > 0;
    // Each entry into or exit from a pixel costs the sampling at most one step; a pixel is entered and
    // left a few times at most here. float storage of the mean adds ~1e-7 relative.
    EXPECT_NEAR(exact, brute[i], 4 * dt + 1e-6 * exact) << "pixel " << i % 256 << "," << i / 256;
  }
  EXPECT_GT(pixels, 100u);
  EXPECT_NEAR(total_exact, total_brute, 0.01 * total_brute + 10 * dt);
}

TEST(CongestionMap, WindowIsTimeInPixelOverWindow) {
  const TrailSet set = traffic();
  expect_window_matches(set, Query{}, kT, kT + 600);
}

TEST(CongestionMap, WindowWithAltitudeBandAndBbox) {
  const TrailSet set = traffic();
  Query f;
  f.alt_min = 4000;  // the climbing flight enters the band half way along its first leg; the hover never
  f.alt_max = 9500;
  expect_window_matches(set, f, kT + 30, kT + 530);
  const auto box = geo::tile_bounds(kTile);
  Query g;
  g.bbox = BBox{box.west, (box.south + box.north) / 2, box.east, box.north};  // the tile's north half
  expect_window_matches(set, g, kT, kT + 600);
}

TEST(CongestionMap, HoveringFlightIsOnePixelForItsWholeTime) {
  const TrailSet set = make({{{kT, 50.0f, 5.0f, 1000}, {kT + 300, 50.0f, 5.0f, 1000}}});
  const density::Canvas c = density::Canvas::for_tile(kTile, 256);
  const density::Raster r = aircraft_per_pixel(set, window(kT - 300, kT + 900), c, std::nullopt);
  const long px = pixel_of(c, 50.0f, 5.0f);
  ASSERT_GE(px, 0);
  EXPECT_FLOAT_EQ(r.values[static_cast<std::size_t>(px)], 300.0f / 1200.0f);
  EXPECT_EQ(r.valid_count(), 1u);
  // At an instant inside its life it counts 1 there; outside, nothing.
  EXPECT_EQ(aircraft_per_pixel(set, Query{}, c, kT + 10).values[static_cast<std::size_t>(px)], 1.0f);
  EXPECT_EQ(aircraft_per_pixel(set, Query{}, c, kT + 301).valid_count(), 0u);
}

TEST(CongestionMap, AcrossTheAntimeridian) {
  // Eastbound across 180° at the equator, 1° in 1000 s: on a zoom-2 tile west of 180° and the one east
  // of it, half the time each.
  const TrailSet set = make({{{kT, 0.5f, 179.5f, 9000}, {kT + 1000, 0.5f, -179.5f, 9000}}});
  const Query q = window(kT, kT + 1000);
  double sum = 0;
  for (const int x : {3, 0}) {
    const density::Raster r =
        aircraft_per_pixel(set, q, density::Canvas::for_tile(geo::TileId{2, x, 1}, 256), std::nullopt);
    double s = 0;
    for (float v : r.values)
      if (!std::isnan(v)) s += v;
    EXPECT_NEAR(s, 0.5, 1e-5) << "tile x=" << x;
    sum += s;
  }
  EXPECT_NEAR(sum, 1.0, 1e-5);
}

TEST(CongestionMap, InstantCountsOnTheEuropeDayMatchPositions) {
  const auto path = test::shared_data("flights/traffic_europe_20180101_m3.so6.gz");
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent";
  const TrailSet set = ingest::ingest_file(path.string());
  for (const double t : {kT + 8 * 3600, kT + 12 * 3600 + 34 * 60 + 56.789, kT + 17 * 3600 + 0.5}) {
    for (const geo::TileId tile : {geo::TileId{3, 4, 2}, geo::TileId{5, 16, 10}, geo::TileId{0, 0, 0}}) {
      const density::Canvas c = density::Canvas::for_tile(tile, 256);
      const density::Raster r = aircraft_per_pixel(set, Query{}, c, t);
      std::vector<int> expected(256 * 256, 0);
      std::size_t on_tile = 0;
      for (const Position& p : positions_at(set, t, Query{}, 100000).positions) {
        const long px = pixel_of(c, p.lat, p.lon);
        if (px >= 0) ++expected[static_cast<std::size_t>(px)], ++on_tile;
      }
      std::size_t counted = 0, wrong = 0;
      for (std::size_t i = 0; i < expected.size(); ++i) {
        const int got = std::isnan(r.values[i]) ? 0 : static_cast<int>(r.values[i]);
        counted += static_cast<std::size_t>(got);
        wrong += got != expected[i];
      }
      EXPECT_EQ(wrong, 0u) << geo::to_string(tile) << " t=" << t;
      EXPECT_EQ(counted, on_tile);
      if (tile.z == 0) EXPECT_GT(on_tile, 500u);
    }
  }
}

TEST(CongestionMap, ThresholdAndShading) {
  // Three hovering aircraft in one pixel, one in another: at an instant, 3 and 1.
  const TrailSet set = make({{{kT, 50.0f, 5.0f, 1000}, {kT + 300, 50.0f, 5.0f, 1000}},
                             {{kT, 50.0f, 5.0f, 2000}, {kT + 300, 50.0f, 5.0f, 2000}},
                             {{kT, 50.0f, 5.0f, 3000}, {kT + 300, 50.0f, 5.0f, 3000}},
                             {{kT, 50.1f, 5.1f, 3000}, {kT + 300, 50.1f, 5.1f, 3000}}});
  CongestionTileRequest r;
  r.tile = kTile;
  r.t = kT + 100;
  r.threshold = 2;
  r.vmax = 4;
  const CongestionTile tile = render_congestion_tile(set, Query{}, r);
  EXPECT_EQ(tile.max_value, 3.0);
  EXPECT_EQ(tile.pixels_above, 1u);
  const density::Image img = density::decode_png(tile.png);
  const density::Canvas c = density::Canvas::for_tile(kTile, 256);
  const long three = pixel_of(c, 50.0f, 5.0f), one = pixel_of(c, 50.1f, 5.1f);
  const auto& fire = density::colormap("fire");
  const std::uint8_t* p3 = img.pixel(static_cast<int>(three % 256), static_cast<int>(three / 256));
  // 3 aircraft between threshold 2 and vmax 4: half way, colormap entry round(0.5 · 255) = 128.
  EXPECT_EQ(p3[0], fire.rgb[128][0]);
  EXPECT_EQ(p3[1], fire.rgb[128][1]);
  EXPECT_EQ(p3[2], fire.rgb[128][2]);
  EXPECT_EQ(p3[3], 255);
  EXPECT_EQ(img.pixel(static_cast<int>(one % 256), static_cast<int>(one / 256))[3], 0);  // 1 < threshold
  std::size_t opaque = 0;
  for (std::size_t i = 3; i < img.rgba.size(); i += 4) opaque += img.rgba[i] != 0;
  EXPECT_EQ(opaque, 1u);
  // Threshold 1: both shown, the single aircraft with the first colour.
  r.threshold = 1;
  const density::Image img1 = density::decode_png(render_congestion_tile(set, Query{}, r).png);
  const std::uint8_t* p1 = img1.pixel(static_cast<int>(one % 256), static_cast<int>(one / 256));
  EXPECT_EQ(p1[0], fire.rgb[0][0]);
  EXPECT_EQ(p1[3], 255);
}

TEST(CongestionMap, BadInput) {
  const TrailSet set = make({{{kT, 50.0f, 5.0f, 1000}, {kT + 300, 50.0f, 5.0f, 1000}}});
  const auto param = [&](const Query& q, const CongestionTileRequest& r) {
    try {
      render_congestion_tile(set, q, r);
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), Error::Kind::invalid_argument);
      return e.param();
    }
    return std::string("(no error)");
  };
  CongestionTileRequest r;
  r.tile = kTile;
  EXPECT_EQ(param(Query{}, r), "t0");  // neither an instant nor a window
  r.t = kT;
  EXPECT_EQ(param(Query{}, r), "(no error)");
  EXPECT_EQ(param(window(kT, kT + 10), r), "t0");  // both
  r.t = NAN;
  EXPECT_EQ(param(Query{}, r), "t");
  r.t.reset();
  Query half;
  half.t0 = kT;
  EXPECT_EQ(param(half, r), "t1");
  EXPECT_EQ(param(window(kT, kT + 10), r), "(no error)");
  r.threshold = 0;
  EXPECT_EQ(param(window(kT, kT + 10), r), "threshold");
  r.threshold = 2;
  r.vmax = 2;
  EXPECT_EQ(param(window(kT, kT + 10), r), "vmax");
  r.vmax.reset();
  r.how = density::How::eq_hist;
  EXPECT_EQ(param(window(kT, kT + 10), r), "how");
  r.how = density::How::log;
  r.cmap = "rainbow";
  EXPECT_EQ(param(window(kT, kT + 10), r), "cmap");
  r.cmap = "viridis";
  r.size = 300;
  EXPECT_EQ(param(window(kT, kT + 10), r), "size");
  r.size = 512;
  r.tile = geo::TileId{3, 8, 0};
  EXPECT_EQ(param(window(kT, kT + 10), r), "x");
}

}  // namespace
}  // namespace trailscope::congestion
