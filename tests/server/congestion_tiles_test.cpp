// The congestion tile route over the real renderer: the PNG against congestion::render_congestion_tile
// called directly, ETag and 304, the cache key, and errors with their exact status, kind and parameter.
#include <gtest/gtest.h>

#include "route_fixture.hpp"
#include "trailscope/congestion/congestion_map.hpp"
#include "trailscope/density/png.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::server {
namespace {

constexpr double kT = 1514764800.0;

class CongestionTilesTest : public test_routes::RouteFixture {
 protected:
  CongestionTilesTest() {
    TrailSetBuilder b;
    // Three aircraft for ten minutes: two hovering on one spot over Amsterdam, one flying south-east from
    // 30 km away (never in their pixel).
    for (int i = 0; i <= 10; ++i) {
      Sample s;
      s.t = kT + i * 60, s.lat = 52.3f, s.lon = 4.76f, s.alt = 3000;
      b.add("4ca1d0", "KLM1", s);
      s.alt = 3500;
      b.add("4ca1d1", "KLM2", s);
      s.lat = 52.0f - i * 0.035f, s.lon = 5.0f + i * 0.06f, s.alt = 10000;
      b.add("4ca1d2", "KLM3", s);
    }
    trails = std::make_shared<const TrailSet>(b.build());
    auto ds = std::make_shared<Dataset>();
    ds->id = "nl", ds->name = "nl", ds->format = "test", ds->created = "2026-01-01T00:00:00Z";
    ds->trails = trails;
    open(ds);
  }
  static void expect_bad(const Response& r, const std::string& param, const std::string& detail) {
    expect_error(r, 400, "invalid_argument", param);
    EXPECT_EQ(body(r).at("detail"), detail) << r.body;
  }
  std::shared_ptr<const TrailSet> trails;
};

// z = 6 tile holding Amsterdam (lon 4.76, lat 52.3): x = 32, y = 21.
constexpr const char* kTile = "/api/v1/datasets/nl/congestion/tiles/6/32/21.png";

TEST_F(CongestionTilesTest, InstantPngIsTheRenderersWithEtagAndCache) {
  const Response r = get(kTile, {{"t", "1514765100"}, {"threshold", "2"}});
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(r.content_type, "image/png");
  congestion::CongestionTileRequest req;
  req.tile = geo::TileId{6, 32, 21};
  req.t = kT + 300;
  req.threshold = 2;
  const congestion::CongestionTile direct = congestion::render_congestion_tile(*trails, Query{}, req);
  EXPECT_EQ(r.bytes(), direct.png);
  EXPECT_EQ(direct.pixels_above, 1u);  // the two hovering aircraft share a pixel; the third is alone
  const density::Image img = density::decode_png(r.bytes());
  std::size_t opaque = 0;
  for (std::size_t i = 3; i < img.rgba.size(); i += 4) opaque += img.rgba[i] != 0;
  EXPECT_EQ(opaque, 1u);
  const std::string etag = header(r, "ETag");
  EXPECT_EQ(etag.size(), 18u);
  EXPECT_EQ(app->tiles.entries(), 1u);
  EXPECT_EQ(get(kTile, {{"t", "1514765100"}, {"threshold", "2"}}).bytes(), r.bytes());
  EXPECT_EQ(app->tiles.entries(), 1u);
  // ISO 8601 and a trailing ".0" give the same instant: the same key, the same ETag.
  EXPECT_EQ(header(get(kTile, {{"t", "2018-01-01T00:05:00Z"}, {"threshold", "2.0"}}), "ETag"), etag);
  const Response not_modified =
      get(kTile, {{"t", "1514765100"}, {"threshold", "2"}}, {{"if-none-match", etag}});
  EXPECT_EQ(not_modified.status, 304);
  EXPECT_TRUE(not_modified.bytes().empty());
  for (const auto& extra : std::vector<std::map<std::string, std::string>>{{{"threshold", "1"}},
                                                                           {{"vmax", "3"}},
                                                                           {{"how", "log"}},
                                                                           {{"cmap", "viridis"}},
                                                                           {{"size", "512"}},
                                                                           {{"alt_max", "5000"}}}) {
    std::map<std::string, std::string> q = {{"t", "1514765100"}, {"threshold", "2"}};
    for (const auto& [k, v] : extra) q[k] = v;
    const Response other = get(kTile, q);
    ASSERT_EQ(other.status, 200) << extra.begin()->first << ": " << other.body;
    EXPECT_NE(header(other, "ETag"), etag) << extra.begin()->first;
  }
}

TEST_F(CongestionTilesTest, WindowIsTheTimeWeightedMean) {
  const Response r = get(kTile, {{"t0", "1514764800"}, {"t1", "1514766000"}, {"threshold", "0.5"}});
  ASSERT_EQ(r.status, 200) << r.body;
  congestion::CongestionTileRequest req;
  req.tile = geo::TileId{6, 32, 21};
  req.threshold = 0.5;
  Query q;
  q.t0 = kT, q.t1 = kT + 1200;
  const congestion::CongestionTile direct = congestion::render_congestion_tile(*trails, q, req);
  EXPECT_EQ(r.bytes(), direct.png);
  // Two aircraft in one pixel for 600 s of a 1200 s window: a mean of 1 there, the tile's largest.
  EXPECT_FLOAT_EQ(static_cast<float>(direct.max_value), 1.0f);
  EXPECT_EQ(direct.pixels_above, 1u);
}

TEST_F(CongestionTilesTest, ErrorsNameTheParameter) {
  const std::map<std::string, std::string> t = {{"t", "1514765100"}};
  const auto with = [&](std::string k, std::string v) {
    auto q = t;
    q[k] = v;
    return q;
  };
  expect_bad(get(kTile), "t0", "t0: give the instant t, or the window t0 and t1");
  expect_bad(get(kTile, {{"t0", "1514764800"}}), "t1", "t1: give the instant t, or the window t0 and t1");
  expect_bad(get(kTile, with("t0", "1514764800")), "t0",
             "t0: give either the instant t or the window t0 and t1, not both");
  expect_bad(get(kTile, with("threshold", "0")), "threshold",
             "threshold: must be a finite number of aircraft > 0");
  expect_bad(get(kTile, with("threshold", "many")), "threshold", "threshold: 'many' is not a number");
  expect_bad(get(kTile, with("vmax", "1")), "vmax", "vmax: must be a finite number of aircraft > threshold");
  expect_bad(get(kTile, with("how", "eq_hist")), "how",
             "how: a congestion tile is shaded 'linear' or 'log' (a fixed span)");
  expect_error(get(kTile, with("how", "cubic")), 400, "invalid_argument", "how");
  expect_error(get(kTile, with("cmap", "rainbow")), 400, "invalid_argument", "cmap");
  expect_error(get(kTile, with("size", "300")), 400, "invalid_argument", "size");
  expect_error(get(kTile, with("t", "soon")), 400, "invalid_argument", "t");
  expect_error(get(kTile, with("kernel", "2")), 400, "invalid_argument", "kernel");
  expect_error(get("/api/v1/datasets/nl/congestion/tiles/23/0/0.png", t), 400, "invalid_argument", "z");
  expect_error(get("/api/v1/datasets/nl/congestion/tiles/3/8/0.png", t), 400, "invalid_argument", "x");
  expect_error(get("/api/v1/datasets/none/congestion/tiles/0/0/0.png", t), 404, "not_found", "dataset");
  // A malformed request never gets a 304, whatever it sends as If-None-Match.
  expect_error(get(kTile, with("cmap", "rainbow"), {{"if-none-match", "*"}}), 400, "invalid_argument",
               "cmap");
}

}  // namespace
}  // namespace trailscope::server
