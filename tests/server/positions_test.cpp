// GET /api/v1/datasets/{dataset}/positions through the real router: JSON and GeoJSON bodies, filters on
// the interpolated position, and every refusal with its exact status, parameter and message.
#include <gtest/gtest.h>

#include "route_fixture.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::server {
namespace {

constexpr double kT0 = 1514764800.0;  // 2018-01-01T00:00:00Z

// KLM1: (52, 4) at 00:00 to (53, 6) at 00:10, 1000 → 2000 m, track 350 → 10; vertical rate unknown at
// the end. DLH2: standing at (50, 8) from 00:00 to 00:20.
std::shared_ptr<Dataset> dataset(const std::string& id) {
  TrailSetBuilder b;
  Sample s;
  s.t = kT0, s.lat = 52, s.lon = 4, s.alt = 1000, s.speed = 200, s.track = 350, s.vrate = 2;
  b.add("4ca1d0", "KLM1", s);
  s.t = kT0 + 600, s.lat = 53, s.lon = 6, s.alt = 2000, s.speed = 220, s.track = 10,
  s.vrate = Sample::kUnknown;
  b.add("4ca1d0", "KLM1", s);
  Sample g;
  g.t = kT0, g.lat = 50, g.lon = 8, g.alt = 100, g.speed = 0, g.on_ground = true;
  b.add("3c6444", "DLH2", g);
  g.t = kT0 + 1200;
  b.add("3c6444", "DLH2", g);
  auto ds = std::make_shared<Dataset>();
  ds->id = id, ds->name = id, ds->format = "test", ds->created = "2026-01-01T00:00:00Z";
  ds->trails = std::make_shared<const TrailSet>(b.build());
  return ds;
}

class PositionsRoute : public test_routes::RouteFixture {
 protected:
  PositionsRoute() { open(dataset("nl")); }
  static constexpr const char* kPath = "/api/v1/datasets/nl/positions";

  void expect_detail(const Response& r, int status, const std::string& param, const std::string& detail) {
    expect_error(r, status,
                 status == 400   ? "invalid_argument"
                 : status == 404 ? "not_found"
                                 : "payload_too_large",
                 param);
    EXPECT_EQ(body(r)["detail"], detail);
  }
};

TEST_F(PositionsRoute, JsonAtAnInstant) {
  const Response r = get(kPath, {{"t", "2018-01-01T00:05:00Z"}});
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(r.content_type, "application/json");
  const auto j = body(r);
  EXPECT_EQ(j["dataset"], "nl");
  EXPECT_EQ(j["t"], kT0 + 300);
  EXPECT_EQ(j["count"], 2);
  ASSERT_EQ(j["positions"].size(), 2u);
  // Ordered by flight id; both start at 00:00, so by icao24: DLH2 (3c6444) is flight 0.
  const auto& dlh = j["positions"][0];
  const auto& klm = j["positions"][1];
  EXPECT_EQ(dlh["id"], 0);
  EXPECT_EQ(dlh["callsign"], "DLH2");
  EXPECT_EQ(dlh["on_ground"], true);
  EXPECT_EQ(klm["id"], 1);
  EXPECT_EQ(klm["icao24"], "4ca1d0");
  EXPECT_EQ(klm["callsign"], "KLM1");
  EXPECT_DOUBLE_EQ(klm["lat"].get<double>(), 52.5);
  EXPECT_DOUBLE_EQ(klm["lon"].get<double>(), 5.0);
  EXPECT_DOUBLE_EQ(klm["alt_m"].get<double>(), 1500.0);
  EXPECT_DOUBLE_EQ(klm["speed_ms"].get<double>(), 210.0);
  EXPECT_DOUBLE_EQ(klm["track_deg"].get<double>(), 0.0);  // 350 → 10 by the shortest arc
  EXPECT_TRUE(klm["vrate_ms"].is_null());
  EXPECT_EQ(klm["exact"], false);
  EXPECT_EQ(klm["on_ground"], false);
  // The same flight id as the flight list and GET .../flights/{id}.
  const auto flight = body(get("/api/v1/datasets/nl/flights/1"));
  EXPECT_EQ(flight["properties"]["callsign"], "KLM1");
  // Unix seconds work as well; after KLM1's last sample only DLH2 is left.
  const auto late = body(get(kPath, {{"t", std::to_string(kT0 + 900)}}));
  EXPECT_EQ(late["count"], 1);
  EXPECT_EQ(late["positions"][0]["callsign"], "DLH2");
  EXPECT_EQ(late["positions"][0]["exact"], false);
  EXPECT_EQ(body(get(kPath, {{"t", "1514764799"}}))["count"], 0);
}

TEST_F(PositionsRoute, GeoJsonPoints) {
  const Response r = get(kPath, {{"t", "1514765100"}, {"format", "geojson"}});
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(r.content_type, "application/geo+json");
  const auto j = body(r);
  EXPECT_EQ(j["type"], "FeatureCollection");
  EXPECT_EQ(j["count"], 2);
  EXPECT_EQ(j["t"], kT0 + 300);
  ASSERT_EQ(j["features"].size(), 2u);
  const auto& klm = j["features"][1];
  EXPECT_EQ(klm["type"], "Feature");
  EXPECT_EQ(klm["id"], 1);
  EXPECT_EQ(klm["geometry"]["type"], "Point");
  EXPECT_EQ(klm["geometry"]["coordinates"], nlohmann::json({5.0, 52.5}));  // [lon, lat]
  EXPECT_EQ(klm["properties"]["callsign"], "KLM1");
  EXPECT_DOUBLE_EQ(klm["properties"]["alt_m"].get<double>(), 1500.0);
  EXPECT_TRUE(klm["properties"]["vrate_ms"].is_null());
  EXPECT_EQ(get(kPath, {{"t", "1514765100"}, {"format", "json"}}).content_type, "application/json");
}

TEST_F(PositionsRoute, FiltersApplyToTheInterpolatedPosition) {
  // KLM1 is at (52.5, 5) at 00:05: a box around that point holds it, though neither sample is inside.
  auto j = body(get(kPath, {{"t", "1514765100"}, {"bbox", "4.9,52.4,5.1,52.6"}}));
  ASSERT_EQ(j["count"], 1);
  EXPECT_EQ(j["positions"][0]["callsign"], "KLM1");
  EXPECT_EQ(body(get(kPath, {{"t", "1514764800"}, {"bbox", "4.9,52.4,5.1,52.6"}}))["count"], 0);
  // 1500 m = 4921 ft: inside 4000–6000 ft, outside 5000–6000 ft; DLH2 at 100 m is outside both.
  EXPECT_EQ(body(get(kPath, {{"t", "1514765100"}, {"alt_min", "4000"}, {"alt_max", "6000"}}))["count"], 1);
  EXPECT_EQ(body(get(kPath, {{"t", "1514765100"}, {"alt_min", "5000"}, {"alt_max", "6000"}}))["count"], 0);
  EXPECT_EQ(body(get(kPath, {{"t", "1514765100"}, {"callsign", "dlh"}}))["count"], 1);
  EXPECT_EQ(body(get(kPath, {{"t", "1514765100"}, {"icao24", "4CA1D0"}}))["count"], 1);
  EXPECT_EQ(body(get(kPath, {{"t", "1514765100"}, {"on_ground", "true"}}))["positions"][0]["callsign"],
            "DLH2");
}

TEST_F(PositionsRoute, RefusalsNameTheParameter) {
  expect_detail(get(kPath), 400, "t", "t: the instant is required (?t=Unix seconds or ISO 8601)");
  expect_detail(get(kPath, {{"t", "soon"}}), 400, "t",
                "t: 'soon' is neither Unix seconds nor an ISO 8601 time such as 2018-01-01T06:00:00Z");
  expect_detail(get(kPath, {{"t", "1514765100"}, {"t0", "1514764800"}}), 400, "t0",
                "t0 does not apply to positions at an instant: give the instant as t");
  expect_detail(get(kPath, {{"t", "1514765100"}, {"t1", "1514766000"}}), 400, "t1",
                "t1 does not apply to positions at an instant: give the instant as t");
  expect_detail(get(kPath, {{"t", "1514765100"}, {"bbox", "1,2,3"}}), 400, "bbox",
                "bbox: expected west,south,east,north in degrees, got '1,2,3'");
  expect_detail(get(kPath, {{"t", "1514765100"}, {"format", "csv"}}), 400, "format",
                "format must be 'json' or 'geojson', got 'csv'");
  expect_detail(get(kPath, {{"t", "1514765100"}, {"max_positions", "0"}}), 400, "max_positions",
                "max_positions must lie in 1..100000, got 0");
  expect_detail(get(kPath, {{"t", "1514765100"}, {"tt", "1"}}), 400, "tt", "unknown query parameter 'tt'");
  expect_error(get("/api/v1/datasets/nope/positions", {{"t", "1514765100"}}), 404, "not_found", "dataset");
  // Over the limit: the client's own cap here, kMaxPositionsPerResponse by default.
  expect_detail(get(kPath, {{"t", "1514765100"}, {"max_positions", "1"}}), 413, "max_positions",
                "2 flights match at t, more than max_positions=1; narrow the answer with bbox, "
                "alt_min/alt_max, callsign or icao24");
  EXPECT_EQ(get(kPath, {{"t", "1514765100"}, {"max_positions", "2"}}).status, 200);
}

TEST_F(PositionsRoute, GarbageParametersNeverGiveServerErrors) {
  const std::vector<std::string> keys = {"t",        "t0",        "t1",       "bbox",
                                         "alt_min",  "alt_max",   "alt_unit", "icao24",
                                         "callsign", "on_ground", "format",   "max_positions"};
  const std::vector<std::string> values = garbage_values(
      {"1514765100", "2018-01-01T00:05:00Z", "geojson", "4,50,6,54", "180,-90,-180,90", "1e20", "-1e20"});
  const int checked = expect_no_server_errors({kPath}, keys, values, 400, 4, 11);
  EXPECT_EQ(checked, 400);
}

}  // namespace
}  // namespace trailscope::server
