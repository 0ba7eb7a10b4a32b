// The density tiles' minimum level and their legend through the real router: the lowest non-empty pixel
// of a count tile is drawn with the colormap entry at min_level (not black), the legend's colours are the
// ones the tiles use and its values those the zoom's shared span (estimate_span, computed here) maps to
// each stop; the refusals with their exact messages.
#include <gtest/gtest.h>

#include <cstdio>
#include <set>

#include "route_fixture.hpp"
#include "trailscope/density/colormap.hpp"
#include "trailscope/density/png.hpp"
#include "trailscope/density/renderer.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::server {
namespace {

constexpr double kT0 = 1514764800.0;

// TWO1 and TWO2 fly the same path at 10° N (pixels of count 2); ONE flies 30° N (count 1). Tile 1/0/0 holds
// their western halves.
std::shared_ptr<Dataset> dataset() {
  TrailSetBuilder b;
  Sample s;
  const std::vector<std::tuple<std::string, std::string, float>> flights = {
      {"aaaaa1", "TWO1", 10.f}, {"aaaaa2", "TWO2", 10.f}, {"aaaaa3", "ONE", 30.f}};
  for (const auto& [icao, cs, lat] : flights) {
    s.lat = lat, s.lon = -40, s.t = kT0, s.alt = 10000;
    b.add(icao, cs, s);
    s.lon = 40, s.t = kT0 + 1200;  // within kFlightGapSeconds: one flight
    b.add(icao, cs, s);
  }
  auto ds = std::make_shared<Dataset>();
  ds->id = "hand", ds->name = "hand", ds->format = "test", ds->created = "2026-01-01T00:00:00Z";
  ds->trails = std::make_shared<const TrailSet>(b.build());
  return ds;
}

// The colormap index of an opaque pixel colour (-1 when the colour is not in the map).
int index_of(const density::Colormap& map, const std::uint8_t* px) {
  for (int k = 0; k < 256; ++k)
    if (map.rgb[k][0] == px[0] && map.rgb[k][1] == px[1] && map.rgb[k][2] == px[2]) return k;
  return -1;
}

class LegendRoute : public test_routes::RouteFixture {
 protected:
  LegendRoute() { open(dataset()); }
  std::set<int> indices(std::map<std::string, std::string> q) {
    const Response r = get("/tiles/hand/density/1/0/0.png", std::move(q));
    EXPECT_EQ(r.status, 200) << r.body;
    const density::Image img = density::decode_png(r.bytes());
    const auto& fire = density::colormap("fire");
    std::set<int> out;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x)
        if (img.pixel(x, y)[3] > 0) out.insert(index_of(fire, img.pixel(x, y)));
    return out;
  }
  void expect_detail(const Response& r, const std::string& param, const std::string& detail) {
    expect_error(r, 400, "invalid_argument", param);
    EXPECT_EQ(body(r)["detail"], detail) << r.body;
  }
};

TEST_F(LegendRoute, LowestBinIsNotBlack) {
  // Default for counts: the lowest non-empty pixel at fire[round(0.25 · 255)] = fire[64], nothing darker.
  const std::set<int> dflt = indices({});
  ASSERT_FALSE(dflt.empty());
  EXPECT_EQ(*dflt.begin(), 64);
  EXPECT_GT(*dflt.rbegin(), 64);
  EXPECT_EQ(dflt.count(-1), 0u);
  // min_level=0 is the former shading: the lowest bin is fire[0], black.
  const std::set<int> zero = indices({{"min_level", "0"}});
  EXPECT_EQ(*zero.begin(), 0);
  EXPECT_GT(*zero.rbegin(), 0);
  EXPECT_EQ(*indices({{"min_level", "0.5"}}).begin(), 128);
  // The same pixels are drawn, only their colours move.
  EXPECT_EQ(zero.size(), dflt.size());
}

TEST_F(LegendRoute, StopsFollowTheSharedSpan) {
  const Response r = get("/api/v1/datasets/hand/density/legend", {{"z", "1"}, {"stops", "5"}});
  ASSERT_EQ(r.status, 200) << r.body;
  const auto j = body(r);
  EXPECT_EQ(j["value"], "count");
  EXPECT_EQ(j["unit"], "segments per pixel");
  EXPECT_EQ(j["how"], "eq_hist");
  EXPECT_EQ(j["min_level"], 0.25);
  EXPECT_EQ(j["empty"], false);
  ASSERT_EQ(j["stops"].size(), 5u);
  // The span the tiles of zoom 1 share, computed here without the server's cache.
  const density::SpanStats span =
      density::estimate_span(*dataset()->trails, Query{}, density::DensityValue::count, 1, 256, 0,
                             std::numeric_limits<double>::infinity(), Backend::cpu);
  EXPECT_EQ(j["lo"].get<double>(), span.lo);
  EXPECT_EQ(j["hi"].get<double>(), span.hi);
  const auto& fire = density::colormap("fire");
  double prev = -1;
  for (int k = 0; k < 5; ++k) {
    const auto& s = j["stops"][k];
    const double t = k / 4.0, v = s["value"].get<double>();
    EXPECT_DOUBLE_EQ(s["t"].get<double>(), t);
    const auto& c = fire.rgb[std::lround((0.25 + t * 0.75) * 255)];
    char hex[8];
    std::snprintf(hex, sizeof hex, "#%02x%02x%02x", c[0], c[1], c[2]);
    EXPECT_EQ(s["color"], hex);
    EXPECT_GE(v, prev);
    prev = v;
    // The smallest value the span normalises to at least t.
    EXPECT_GE(span.normalize(v, density::How::eq_hist) + 1e-9, t) << k;
    if (k > 0) EXPECT_LT(span.normalize(v - 1e-6 * (span.hi - span.lo), density::How::eq_hist), t) << k;
  }
  EXPECT_EQ(j["stops"][0]["value"].get<double>(), span.lo);
  EXPECT_NEAR(j["stops"][4]["value"].get<double>(), span.hi, 1e-6 * (span.hi - span.lo));
  // Linear: evenly spaced values.
  const auto lin =
      body(get("/api/v1/datasets/hand/density/legend", {{"z", "1"}, {"stops", "3"}, {"how", "linear"}}));
  EXPECT_NEAR(lin["stops"][1]["value"].get<double>(), (span.lo + span.hi) / 2, 1e-6 * (span.hi - span.lo));
  // An empty window: no stops.
  const auto none = body(get("/api/v1/datasets/hand/density/legend", {{"z", "1"}, {"t0", "0"}, {"t1", "1"}}));
  EXPECT_EQ(none["empty"], true);
  EXPECT_TRUE(none["stops"].empty());
  // Altitude: no floor by default, metres.
  const auto alt = body(
      get("/api/v1/datasets/hand/density/legend", {{"z", "1"}, {"value", "altitude"}, {"how", "linear"}}));
  EXPECT_EQ(alt["min_level"], 0);
  EXPECT_EQ(alt["unit"], "m");
}

TEST_F(LegendRoute, Refusals) {
  const std::string path = "/api/v1/datasets/hand/density/legend";
  expect_detail(get(path), "z", "z: the zoom of the tiles is required (?z=)");
  expect_detail(get(path, {{"z", "23"}}), "z", "z must lie in 0..22, got 23");
  expect_detail(get(path, {{"z", "1"}, {"stops", "1"}}), "stops", "stops must lie in 2..256, got 1");
  expect_detail(get(path, {{"z", "1"}, {"min_level", "1"}}), "min_level",
                "min_level must lie in [0, 1), got 1");
  expect_detail(get(path, {{"z", "1"}, {"cmap", "jet"}}), "cmap",
                body(get("/tiles/hand/density/1/0/0.png", {{"cmap", "jet"}}))["detail"]);
  expect_detail(get("/tiles/hand/density/1/0/0.png", {{"min_level", "1.5"}}), "min_level",
                "min_level must lie in [0, 1), got 1.5");
  expect_detail(get("/tiles/hand/density/1/0/0.png", {{"min_level", "-0.1"}}), "min_level",
                "min_level must lie in [0, 1), got -0.1");
}

}  // namespace
}  // namespace trailscope::server
