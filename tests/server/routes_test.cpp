// The real router, built in process over a real store: exact statuses, content types and error bodies.
#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "route_fixture.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::server {
namespace {

std::shared_ptr<Dataset> small_dataset(const std::string& id) {
  TrailSetBuilder b;
  // Two flights over the Netherlands, one sample a minute from 2018-01-01T00:00Z.
  for (int i = 0; i < 60; ++i) {
    Sample s;
    s.t = 1514764800.0 + i * 60, s.lat = 52.0f + i * 0.01f, s.lon = 4.0f + i * 0.02f;
    s.alt = static_cast<float>(i * 100), s.speed = 200;
    b.add("4ca1d0", "KLM1", s);
    s.lat += 0.5f, s.alt = 10000;
    b.add("3c6444", "DLH2", s);
  }
  auto ds = std::make_shared<Dataset>();
  ds->id = id, ds->name = id, ds->format = "test", ds->created = "2026-01-01T00:00:00Z";
  ds->trails = std::make_shared<const TrailSet>(b.build());
  return ds;
}

class RoutesTest : public test_routes::RouteFixture {
 protected:
  RoutesTest() { open(small_dataset("nl")); }
};

TEST_F(RoutesTest, HealthAndDatasets) {
  auto r = get("/api/v1/health");
  EXPECT_EQ(r.status, 200);
  EXPECT_EQ(body(r)["status"], "ok");
  r = get("/api/v1/datasets");
  ASSERT_EQ(r.status, 200);
  ASSERT_EQ(body(r)["datasets"].size(), 1u);
  EXPECT_EQ(body(r)["datasets"][0]["flights"], 2);
  EXPECT_EQ(body(r)["datasets"][0]["points"], 120);
  r = get("/api/v1/datasets/nl");
  EXPECT_EQ(body(r)["bbox"][1], 52.0);
}

TEST_F(RoutesTest, SummaryMatchesFilters) {
  // 00:10 ≤ t < 00:20 and below 5000 ft: only KLM1 (alt i·100 m ≤ 1524 m → i ≤ 15), samples 10..15.
  auto r = get("/api/v1/datasets/nl/summary",
               {{"t0", "2018-01-01T00:10:00Z"}, {"t1", "1514766000"}, {"alt_max", "5000"}});
  ASSERT_EQ(r.status, 200) << r.body;
  const auto j = body(r);
  EXPECT_EQ(j["flights"], 1);
  EXPECT_EQ(j["points"], 6);
  EXPECT_EQ(j["top_callsigns"][0]["callsign"], "KLM1");
  EXPECT_EQ(j["dataset"], "nl");
}

TEST_F(RoutesTest, FlightsAndGeoJson) {
  auto r = get("/api/v1/datasets/nl/flights", {{"callsign", "DLH"}});
  ASSERT_EQ(r.status, 200);
  auto j = body(r);
  EXPECT_EQ(j["total"], 1);
  const int id = j["flights"][0]["id"];
  r = get("/api/v1/datasets/nl/flights/" + std::to_string(id));
  ASSERT_EQ(r.status, 200);
  EXPECT_EQ(r.content_type, "application/geo+json");
  j = body(r);
  EXPECT_EQ(j["geometry"]["type"], "LineString");
  EXPECT_EQ(j["geometry"]["coordinates"].size(), 60u);
  EXPECT_EQ(j["properties"]["callsign"], "DLH2");
  r = get("/api/v1/datasets/nl/flights/" + std::to_string(id), {{"max_points", "10"}});
  expect_error(r, 413, "payload_too_large", "max_points");
}

TEST_F(RoutesTest, ErrorsNameTheParameter) {
  expect_error(get("/api/v1/datasets/nope"), 404, "not_found", "dataset");
  expect_error(get("/api/v1/datasets/nl/summary", {{"t0", "soon"}}), 400, "invalid_argument", "t0");
  expect_error(get("/api/v1/datasets/nl/summary", {{"t0", "10"}, {"t1", "5"}}), 400, "invalid_argument",
               "t1");
  expect_error(get("/api/v1/datasets/nl/summary", {{"bbox", "1,2,3"}}), 400, "invalid_argument", "bbox");
  expect_error(get("/api/v1/datasets/nl/summary", {{"t_0", "10"}}), 400, "invalid_argument", "t_0");
  expect_error(get("/api/v1/datasets/nl/summary", {{"bins", "0"}}), 400, "invalid_argument", "bins");
  expect_error(get("/api/v1/datasets/nl/flights", {{"page_size", "1001"}}), 400, "invalid_argument",
               "page_size");
  expect_error(get("/api/v1/datasets/nl/flights/99"), 404, "not_found", "flight_id");
  expect_error(get("/api/v1/datasets/nl/flights/x1"), 400, "invalid_argument", "flight_id");
  expect_error(get("/api/v1/jobs/j999"), 404, "not_found", "job");
  expect_error(get("/api/v1/nothing"), 404, "not_found", "path");
  Request del;
  del.method = "PUT", del.path = "/api/v1/datasets/nl";
  const Response r = router.handle(del);
  EXPECT_EQ(r.status, 405);
}

TEST_F(RoutesTest, UploadRunsAnIngestJob) {
  Request r;
  r.method = "POST", r.path = "/api/v1/datasets", r.query = {{"name", "up"}};
  r.body =
      "time,icao24,lat,lon,velocity,heading,vertrate,callsign,onground,alert,spi,squawk,baroaltitude,"
      "geoaltitude,"
      "lastposupdate,lastcontact\n"
      "1514764800,4ca1d0,52.3,4.76,100,90,0,KLM1,false,false,false,1000,1000,1010,1514764800,1514764800\n"
      "1514764810,4ca1d0,52.3,4.78,100,90,0,KLM1,false,false,false,1000,1000,1010,1514764810,1514764810\n"
      "1514764820,4ca1d0,95.0,4.80,100,90,0,KLM1,false,false,false,1000,1000,1010,1514764820,1514764820\n";
  Response res = router.handle(r);
  ASSERT_EQ(res.status, 202) << res.body;
  const std::string job = body(res)["job"]["id"];
  const JobState done = app->jobs.wait(job);
  ASSERT_EQ(done.state, "done") << done.to_json().dump();
  const auto ds = body(get("/api/v1/datasets/up"));
  EXPECT_EQ(ds["points"], 2);
  EXPECT_EQ(ds["ingest"]["rejected"], 1);
  // The same name again is a conflict, decided before any work starts.
  res = router.handle(r);
  expect_error(res, 409, "conflict", "name");
  r.query = {{"name", "Bad Name"}};
  expect_error(router.handle(r), 400, "invalid_argument", "name");
  r.query = {{"name", "fmt"}, {"format", "xml"}};
  expect_error(router.handle(r), 400, "invalid_argument", "format");
}

TEST_F(RoutesTest, UploadOfNonTrailDataFailsTheJob) {
  Request r;
  r.method = "POST", r.path = "/api/v1/datasets", r.query = {{"name", "junk"}};
  r.body = "\x89PNG\r\n\x1a\n not a trail file";
  const Response res = router.handle(r);
  ASSERT_EQ(res.status, 202);
  const JobState done = app->jobs.wait(body(res)["job"]["id"]);
  EXPECT_EQ(done.state, "failed");
  EXPECT_EQ(done.error["error"], "unsupported_format");
  expect_error(get("/api/v1/datasets/junk"), 404, "not_found", "dataset");
}

TEST_F(RoutesTest, DeleteDataset) {
  Request r;
  r.method = "DELETE", r.path = "/api/v1/datasets/nl";
  r.principal = principal;
  EXPECT_EQ(router.handle(r).status, 204);
  expect_error(router.handle(r), 404, "not_found", "dataset");
  // Gone for good: a store reopened on the same folder does not bring it back.
  EmbeddedStore reopened(tmp.path() / "store");
  EXPECT_FALSE(reopened.contains("nl"));
}

}  // namespace
}  // namespace trailscope::server

namespace trailscope::server {
namespace {

// Garbage in every parameter of every read route: always a 2xx or a 4xx with a JSON error body, never
// a 5xx and never an exception out of the router.
TEST_F(RoutesTest, GarbageParametersNeverGiveServerErrors) {
  const std::vector<std::string> paths = {"/api/v1/datasets/nl/summary",   "/api/v1/datasets/nl/flights",
                                          "/api/v1/datasets/nl/flights/0", "/tiles/nl/density/6/32/21.png",
                                          "/api/v1/datasets/nl",           "/api/v1/jobs/j1"};
  const std::vector<std::string> keys = {"bbox",     "t0",     "t1",        "alt_min",   "alt_max",
                                         "alt_unit", "icao24", "callsign",  "on_ground", "bins",
                                         "top",      "page",   "page_size", "clip",      "max_points",
                                         "value",    "how",    "cmap",      "size",      "kernel"};
  const std::vector<std::string> values =
      garbage_values({"1,2,3,4,5", ",,,", "180,-90,-180,90", "2018-02-30T25:61:61Z", "%00", "a*b?c*", "1.5",
                      "1514764800,1514764801"});
  const int checked = expect_no_server_errors(paths, keys, values, 200, 4, 7);
  EXPECT_EQ(checked, 1200);
}

}  // namespace
}  // namespace trailscope::server
