// GET /api/v1/datasets/{dataset}/pick through the real router: distances on hand-made trails computed here
// from the Web Mercator formula, the antimeridian, windows that leave a lone sample, and the real Europe
// day against a brute force written here (every drawn segment of every flight, pixel positions from
// lon/lat in double, the distance as perpendicular or endpoint distance); every refusal with its exact
// status, parameter and message.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "europe_dataset.hpp"
#include "route_fixture.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::server {
namespace {

constexpr double kT0 = 1514764800.0;  // 2018-01-01T00:00:00Z

// World pixels of a lon/lat at a zoom (the slippy-map formula, written here from the definition).
struct Px {
  double x, y;
};
Px world_px(double lon, double lat, double zoom, int tile_size) {
  const double w = tile_size * std::pow(2.0, zoom);
  const double phi = lat * std::numbers::pi / 180;
  return {(lon + 180) / 360 * w,
          (1 - std::log(std::tan(std::numbers::pi / 4 + phi / 2)) / std::numbers::pi) / 2 * w};
}

// EQ: along the equator from 0° to 10° E in 1000 s, 1000 → 2000 m. SOUTH: the same at 0.006° S.
// DATE: across 180° at 10° N, 179° E → 179° W. ONE: a single sample.
std::shared_ptr<Dataset> dataset(const std::string& id) {
  TrailSetBuilder b;
  Sample s;
  s.speed = 200;
  for (auto [cs, lat] : {std::pair{"EQ", 0.0}, {"SOUTH", -0.006}}) {
    s.t = kT0, s.lat = lat, s.lon = 0, s.alt = 1000;
    b.add(std::string(cs) == "EQ" ? "aaaaa1" : "aaaaa2", cs, s);
    s.t = kT0 + 1000, s.lon = 10, s.alt = 2000;
    b.add(std::string(cs) == "EQ" ? "aaaaa1" : "aaaaa2", cs, s);
  }
  s.t = kT0, s.lat = 10, s.lon = 179, s.alt = 9000;
  b.add("aaaaa3", "DATE", s);
  s.t = kT0 + 600, s.lon = -179;
  b.add("aaaaa3", "DATE", s);
  s.t = kT0, s.lat = 0.001, s.lon = 5;
  b.add("aaaaa4", "ONE", s);
  auto ds = std::make_shared<Dataset>();
  ds->id = id, ds->name = id, ds->format = "test", ds->created = "2026-01-01T00:00:00Z";
  ds->trails = std::make_shared<const TrailSet>(b.build());
  return ds;
}

class PickRoute : public test_routes::RouteFixture {
 protected:
  PickRoute() { open(dataset("hand")); }
  static constexpr const char* kPath = "/api/v1/datasets/hand/pick";
  void expect_detail(const Response& r, int status, const std::string& param, const std::string& detail) {
    expect_error(r, status, status == 400 ? "invalid_argument" : "not_found", param);
    EXPECT_EQ(body(r)["detail"], detail) << r.body;
  }
};

TEST_F(PickRoute, NearestFirstWithDistancesInScreenPixels) {
  const double zoom = 10, lat = 0.003;
  const Response r = get(kPath, {{"lon", "5"}, {"lat", "0.003"}, {"zoom", "10"}, {"tolerance", "10"}});
  ASSERT_EQ(r.status, 200) << r.body;
  const auto j = body(r);
  EXPECT_EQ(j["tile_size"], 256);
  EXPECT_EQ(j["tolerance_px"], 10);
  ASSERT_EQ(j["flights"].size(), 2u) << r.body;  // ONE is a lone sample: nothing drawn, never picked
  const double d_eq = world_px(5, 0, zoom, 256).y - world_px(5, lat, zoom, 256).y;
  const double d_south = world_px(5, -0.006, zoom, 256).y - world_px(5, lat, zoom, 256).y;
  const auto& eq = j["flights"][0];
  EXPECT_EQ(eq["callsign"], "EQ");
  EXPECT_EQ(eq["icao24"], "aaaaa1");
  EXPECT_NEAR(eq["distance_px"].get<double>(), d_eq, 1e-3);
  EXPECT_NEAR(eq["t"].get<double>(), kT0 + 500, 1e-3);  // halfway along in x, so halfway in time
  EXPECT_NEAR(eq["lon"].get<double>(), 5, 1e-6);
  EXPECT_NEAR(eq["lat"].get<double>(), 0, 1e-6);
  EXPECT_NEAR(eq["alt_m"].get<double>(), 1500, 1e-3);
  EXPECT_EQ(j["flights"][1]["callsign"], "SOUTH");
  EXPECT_NEAR(j["flights"][1]["distance_px"].get<double>(), d_south, 1e-3);
  // d_south is about 6.5 px: the default tolerance of 5 px leaves it out.
  ASSERT_GT(d_south, 5);
  const auto near = body(get(kPath, {{"lon", "5"}, {"lat", "0.003"}, {"zoom", "10"}}));
  ASSERT_EQ(near["flights"].size(), 1u);
  EXPECT_EQ(near["flights"][0]["callsign"], "EQ");
  // limit keeps the nearest.
  const auto one =
      body(get(kPath, {{"lon", "5"}, {"lat", "0.003"}, {"zoom", "10"}, {"tolerance", "10"}, {"limit", "1"}}));
  ASSERT_EQ(one["flights"].size(), 1u);
  EXPECT_EQ(one["flights"][0]["callsign"], "EQ");
  // A 512-px world at zoom 9 is the 256-px world at zoom 10: the same distances.
  const auto big = body(
      get(kPath, {{"lon", "5"}, {"lat", "0.003"}, {"zoom", "9"}, {"tile_size", "512"}, {"tolerance", "10"}}));
  ASSERT_EQ(big["flights"].size(), 2u);
  EXPECT_NEAR(big["flights"][0]["distance_px"].get<double>(), d_eq, 1e-3);
}

TEST_F(PickRoute, WorldPixelsGiveTheSameAnswerAsLonLat) {
  const Px p = world_px(5, 0.003, 10, 256);
  char x[64], y[64];
  std::snprintf(x, sizeof x, "%.9f", p.x), std::snprintf(y, sizeof y, "%.9f", p.y);
  const auto by_px = body(get(kPath, {{"x", x}, {"y", y}, {"zoom", "10"}, {"tolerance", "10"}}));
  const auto by_geo = body(get(kPath, {{"lon", "5"}, {"lat", "0.003"}, {"zoom", "10"}, {"tolerance", "10"}}));
  ASSERT_EQ(by_px["flights"].size(), by_geo["flights"].size());
  for (std::size_t i = 0; i < by_px["flights"].size(); ++i) {
    EXPECT_EQ(by_px["flights"][i]["id"], by_geo["flights"][i]["id"]);
    EXPECT_NEAR(by_px["flights"][i]["distance_px"].get<double>(),
                by_geo["flights"][i]["distance_px"].get<double>(), 1e-6);
  }
}

TEST_F(PickRoute, AcrossTheAntimeridianFromBothSides) {
  for (const char* lon : {"179.5", "-179.5", "180", "-180"}) {
    const auto j = body(get(kPath, {{"lon", lon}, {"lat", "10"}, {"zoom", "6"}}));
    ASSERT_EQ(j["flights"].size(), 1u) << lon;
    EXPECT_EQ(j["flights"][0]["callsign"], "DATE");
    EXPECT_LT(j["flights"][0]["distance_px"].get<double>(), 1e-3) << lon;
  }
  // Halfway, at 180°: the time is halfway too.
  const auto mid = body(get(kPath, {{"lon", "180"}, {"lat", "10"}, {"zoom", "6"}}));
  EXPECT_NEAR(mid["flights"][0]["t"].get<double>(), kT0 + 300, 1e-3);
  // The long way round (through 0°) is not drawn, so 0° E is far from DATE.
  const auto far = body(get(kPath, {{"lon", "0"}, {"lat", "10"}, {"zoom", "6"}}));
  EXPECT_TRUE(far["flights"].empty());
}

TEST_F(PickRoute, FiltersAsTheTilesApplyThem) {
  // A window holding only one end of each segment draws nothing.
  const auto cut =
      body(get(kPath, {{"lon", "5"}, {"lat", "0"}, {"zoom", "10"}, {"t0", std::to_string(kT0 + 1)}}));
  EXPECT_TRUE(cut["flights"].empty());
  const auto band = body(
      get(kPath, {{"lon", "5"}, {"lat", "0"}, {"zoom", "10"}, {"tolerance", "10"}, {"alt_min", "3000"}}));
  // alt_min=3000 ft is 914.4 m, below both ends (1000 and 2000 m) of both flights: both stay.
  ASSERT_EQ(band["flights"].size(), 2u);
  const auto callsign = body(
      get(kPath, {{"lon", "5"}, {"lat", "0"}, {"zoom", "10"}, {"tolerance", "10"}, {"callsign", "SOU"}}));
  ASSERT_EQ(callsign["flights"].size(), 1u);
  EXPECT_EQ(callsign["flights"][0]["callsign"], "SOUTH");
  const auto high = body(get(kPath, {{"lon", "5"}, {"lat", "0"}, {"zoom", "10"}, {"alt_min", "4000"}}));
  EXPECT_TRUE(high["flights"].empty());  // 4000 ft = 1219 m: the first sample (1000 m) fails
}

TEST_F(PickRoute, Refusals) {
  expect_detail(get(kPath, {{"lon", "5"}, {"lat", "0"}}), 400, "zoom",
                "zoom: the map's zoom is required (?zoom=)");
  expect_detail(get(kPath, {{"zoom", "3"}}), 400, "lon",
                "the point is required: lon and lat, or x and y in world pixels");
  expect_detail(get(kPath, {{"lon", "5"}, {"zoom", "3"}}), 400, "lat", "lon and lat go together");
  expect_detail(get(kPath, {{"y", "5"}, {"zoom", "3"}}), 400, "x", "x and y go together");
  expect_detail(get(kPath, {{"lon", "5"}, {"lat", "0"}, {"x", "1"}, {"y", "1"}, {"zoom", "3"}}), 400, "x",
                "give the point either as lon and lat or as x and y, not both");
  expect_detail(get(kPath, {{"lon", "5"}, {"lat", "91"}, {"zoom", "3"}}), 400, "lat",
                "lat must lie in [-90, 90]");
  expect_detail(get(kPath, {{"lon", "5"}, {"lat", "0"}, {"zoom", "23"}}), 400, "zoom",
                "zoom must lie in 0..22");
  expect_detail(get(kPath, {{"lon", "5"}, {"lat", "0"}, {"zoom", "x"}}), 400, "zoom",
                "zoom: 'x' is not a number");
  expect_detail(get(kPath, {{"lon", "5"}, {"lat", "0"}, {"zoom", "3"}, {"tile_size", "300"}}), 400,
                "tile_size", "tile_size must be 256 or 512");
  expect_detail(get(kPath, {{"lon", "5"}, {"lat", "0"}, {"zoom", "3"}, {"tolerance", "0"}}), 400, "tolerance",
                "tolerance must lie in (0, 32] pixels");
  expect_detail(get(kPath, {{"lon", "5"}, {"lat", "0"}, {"zoom", "3"}, {"tolerance", "33"}}), 400,
                "tolerance", "tolerance must lie in (0, 32] pixels");
  expect_detail(get(kPath, {{"lon", "5"}, {"lat", "0"}, {"zoom", "3"}, {"limit", "101"}}), 400, "limit",
                "limit must lie in 1..100, got 101");
  expect_detail(get(kPath, {{"x", "5"}, {"y", "2049"}, {"zoom", "3"}}), 400, "y",
                "y must lie in [0, 2048] (world pixels at this zoom)");
  expect_detail(get(kPath, {{"lon", "5"}, {"lat", "0"}, {"zoom", "3"}, {"t1", "0"}, {"t0", "10"}}), 400, "t1",
                body(get("/api/v1/datasets/hand/summary", {{"t1", "0"}, {"t0", "10"}}))["detail"]);
  expect_detail(get(kPath, {{"lon", "5"}, {"lat", "0"}, {"zoom", "3"}, {"page", "1"}}), 400, "page",
                body(get("/api/v1/datasets/hand/summary", {{"page", "1"}}))["detail"]);
  expect_detail(get("/api/v1/datasets/nope/pick", {{"lon", "5"}, {"lat", "0"}, {"zoom", "3"}}), 404,
                "dataset", body(get("/api/v1/datasets/nope"))["detail"]);
  EXPECT_GT(
      expect_no_server_errors({kPath}, {"lon", "lat", "x", "y", "zoom", "tile_size", "tolerance", "limit"},
                              garbage_values({"5", "0", "512", "3.5"}), 200, 6, 17),
      0);
}

// The Europe day: the route against a brute force over every drawn segment of every flight.
class PickEurope : public test_routes::RouteFixture {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(test_routes::europe_so6())) GTEST_SKIP() << "the Europe SO6 day is absent";
    open(test_routes::europe_dataset("eu"));
  }
};

TEST_F(PickEurope, EqualsBruteForce) {
  const TrailSet& set = *test_routes::europe_trails();
  const auto& p = set.points();
  struct Case {
    double lon, lat, zoom;
    int tile;
    double t0, t1, tol;
  };
  const std::vector<Case> cases = {{8.57, 50.03, 8, 512, kT0 + 8 * 3600, kT0 + 9 * 3600, 10},     // Frankfurt
                                   {-0.45, 51.47, 11, 256, kT0 + 6 * 3600, kT0 + 12 * 3600, 8},   // Heathrow
                                   {2.35, 48.85, 6.5, 512, kT0 + 12 * 3600, kT0 + 13 * 3600, 4},  // Paris
                                   {14.0, 45.0, 5, 256, kT0, kT0 + 86400, 3}};
  int compared = 0;
  for (const Case& c : cases) {
    // Brute force: every flight, every pair of consecutive samples both inside [t0, t1).
    std::vector<std::pair<double, std::uint32_t>> expect;
    const Px q = world_px(c.lon, c.lat, c.zoom, c.tile);
    for (std::uint32_t fi = 0; fi < set.num_flights(); ++fi) {
      const Flight& f = set.flights()[fi];
      double best = INFINITY;
      for (std::size_t i = f.begin; i + 1 < f.end; ++i) {
        if (!(p.t[i] >= c.t0 && p.t[i] < c.t1 && p.t[i + 1] >= c.t0 && p.t[i + 1] < c.t1)) continue;
        const Px a = world_px(p.lon[i], p.lat[i], c.zoom, c.tile),
                 b = world_px(p.lon[i + 1], p.lat[i + 1], c.zoom, c.tile);
        const double abx = b.x - a.x, aby = b.y - a.y;
        const double da = std::hypot(q.x - a.x, q.y - a.y), db = std::hypot(q.x - b.x, q.y - b.y);
        double d = std::min(da, db);
        // Perpendicular distance when the foot lies between the ends: |cross| / |ab|.
        const double len = std::hypot(abx, aby);
        if (len > 0 && (q.x - a.x) * abx + (q.y - a.y) * aby > 0 && (q.x - b.x) * abx + (q.y - b.y) * aby < 0)
          d = std::abs(abx * (q.y - a.y) - aby * (q.x - a.x)) / len;
        best = std::min(best, d);
      }
      if (best <= c.tol) expect.emplace_back(best, fi);
    }
    std::sort(expect.begin(), expect.end());
    char lon[32], lat[32], zoom[32], tol[32];
    std::snprintf(lon, sizeof lon, "%g", c.lon), std::snprintf(lat, sizeof lat, "%g", c.lat);
    std::snprintf(zoom, sizeof zoom, "%g", c.zoom), std::snprintf(tol, sizeof tol, "%g", c.tol);
    const Response r = get("/api/v1/datasets/eu/pick", {{"lon", lon},
                                                        {"lat", lat},
                                                        {"zoom", zoom},
                                                        {"tile_size", std::to_string(c.tile)},
                                                        {"tolerance", tol},
                                                        {"limit", "100"},
                                                        {"t0", std::to_string(c.t0)},
                                                        {"t1", std::to_string(c.t1)}});
    ASSERT_EQ(r.status, 200) << r.body;
    const auto got = body(r)["flights"];
    ASSERT_GT(expect.size(), 0u) << c.lon << "," << c.lat;
    const std::size_t n = std::min<std::size_t>(expect.size(), 100);
    // The positions are float32 in the store and 2^-32 of the world in Mercator: distances agree to far
    // less than 1e-3 px; flights that close to the tolerance or to each other are compared by distance only.
    ASSERT_EQ(got.size(), n) << c.lon << "," << c.lat;
    for (std::size_t k = 0; k < n; ++k) {
      EXPECT_NEAR(got[k]["distance_px"].get<double>(), expect[k].first, 1e-3) << k;
      const bool tie = (k > 0 && expect[k].first - expect[k - 1].first < 1e-3) ||
                       (k + 1 < expect.size() && expect[k + 1].first - expect[k].first < 1e-3);
      if (!tie) EXPECT_EQ(got[k]["id"], expect[k].second) << k;
      EXPECT_EQ(got[k]["callsign"], set.flights()[got[k]["id"].get<std::uint32_t>()].callsign);
      ++compared;
    }
  }
  EXPECT_GT(compared, 20);
}

}  // namespace
}  // namespace trailscope::server
