// The density tile route over the real renderer: PNG bytes, ETag and 304, the cache, and errors that
// name their parameter.
#include <gtest/gtest.h>

#include "route_fixture.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::server {
namespace {

class TilesTest : public test_routes::RouteFixture {
 protected:
  TilesTest() {
    TrailSetBuilder b;
    // A flight from Amsterdam towards Frankfurt, one sample a minute.
    for (int i = 0; i <= 60; ++i) {
      Sample s;
      s.t = 1514764800.0 + i * 60, s.lat = 52.3f - i * 0.035f, s.lon = 4.76f + i * 0.06f, s.alt = 10000,
      s.speed = 220;
      b.add("4ca1d0", "KLM1", s);
    }
    auto ds = std::make_shared<Dataset>();
    ds->id = "nl", ds->name = "nl", ds->format = "test", ds->created = "2026-01-01T00:00:00Z";
    ds->trails = std::make_shared<const TrailSet>(b.build());
    open(ds);
  }
  static void expect_bad(const Response& r, const std::string& param) {
    expect_error(r, 400, "invalid_argument", param);
  }
};

// z = 6 tile holding Amsterdam (lon 4.76, lat 52.3): x = floor((4.76+180)/360·64) = 32, y = 21.
constexpr const char* kTile = "/tiles/nl/density/6/32/21.png";

TEST_F(TilesTest, PngWithEtagAndCache) {
  const Response r = get(kTile);
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(r.content_type, "image/png");
  ASSERT_GT(r.bytes().size(), 8u);
  EXPECT_EQ(r.bytes().substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  const std::string etag = header(r, "ETag");
  EXPECT_EQ(etag.size(), 18u);
  EXPECT_FALSE(header(r, "Cache-Control").empty());
  EXPECT_EQ(app->tiles.entries(), 1u);
  // The same request again is served from the cache with the same bytes.
  const Response again = get(kTile);
  EXPECT_EQ(again.bytes(), r.bytes());
  EXPECT_EQ(app->tiles.entries(), 1u);
  // If-None-Match with the ETag: 304, no body.
  const Response not_modified = get(kTile, {}, {{"if-none-match", etag}});
  EXPECT_EQ(not_modified.status, 304);
  EXPECT_TRUE(not_modified.bytes().empty());
  EXPECT_EQ(header(not_modified, "ETag"), etag);
  // Any input that changes the bytes changes the ETag.
  for (const auto& q : std::vector<std::map<std::string, std::string>>{{{"cmap", "viridis"}},
                                                                       {{"how", "log"}},
                                                                       {{"value", "altitude"}},
                                                                       {{"size", "512"}},
                                                                       {{"kernel", "2"}},
                                                                       {{"t0", "1514765000"}}}) {
    const Response other = get(kTile, q);
    ASSERT_EQ(other.status, 200) << q.begin()->first << ": " << other.body;
    EXPECT_NE(header(other, "ETag"), etag) << q.begin()->first;
  }
}

TEST_F(TilesTest, EmptyTileIsATransparentPng) {
  const Response r = get("/tiles/nl/density/6/0/0.png");
  ASSERT_EQ(r.status, 200);
  EXPECT_EQ(r.content_type, "image/png");
}

TEST_F(TilesTest, ErrorsNameTheParameter) {
  expect_bad(get("/tiles/nl/density/23/0/0.png"), "z");
  expect_bad(get("/tiles/nl/density/3/8/0.png"), "x");
  expect_bad(get("/tiles/nl/density/3/0/-1.png"), "y");
  expect_bad(get("/tiles/nl/density/a/0/0.png"), "z");
  expect_bad(get(kTile, {{"value", "heat"}}), "value");
  expect_bad(get(kTile, {{"how", "cubic"}}), "how");
  expect_bad(get(kTile, {{"cmap", "rainbow"}}), "cmap");
  expect_bad(get(kTile, {{"size", "300"}}), "size");
  expect_bad(get(kTile, {{"kernel", "33"}}), "kernel");
  expect_bad(get(kTile, {{"t0", "late"}}), "t0");
  expect_bad(get(kTile, {{"zoom", "1"}}), "zoom");
  expect_error(get("/tiles/none/density/0/0/0.png"), 404, "not_found", "dataset");
  // A malformed request never gets a 304, whatever it sends as If-None-Match.
  expect_bad(get(kTile, {{"cmap", "rainbow"}}, {{"if-none-match", "*"}}), "cmap");
}

}  // namespace
}  // namespace trailscope::server
