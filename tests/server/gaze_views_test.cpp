// The gaze views over the API, in process (routes/gaze_views.cpp): stimulus-space tiles and their legend
// against binning done here on the stored recordings, AOI answers against a brute-force count over the
// events route's fixations, a saccade bundle job whose result sits in the bundle store, and the exact
// statuses and messages of bad requests.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "route_fixture.hpp"
#include "test_support.hpp"
#include "trailscope/density/png.hpp"
#include "trailscope/gaze/ingest.hpp"
#include "trailscope/gaze/query.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::server {
namespace {

std::shared_ptr<Dataset> one_flight() {
  TrailSetBuilder b;
  for (int i = 0; i < 3; ++i) {
    Sample s;
    s.t = 1514764800.0 + i * 60, s.lat = 52.0f, s.lon = 4.0f + i * 0.1f, s.alt = 1000, s.speed = 200;
    b.add("4ca100", "KLM1", s);
  }
  auto ds = std::make_shared<Dataset>();
  ds->id = "f", ds->name = "f", ds->format = "test", ds->created = "2026-01-01T00:00:00Z";
  ds->trails = std::make_shared<const TrailSet>(b.build());
  return ds;
}

/// The two Lund recordings of the Europe image (1024 x 768 px screen, 38 x 30 cm at 67 cm).
std::shared_ptr<const gaze::GazeDataset> lund() {
  gaze::GazeIngestOptions o;
  o.geometry = {1024, 768, 38, 30, 67};
  auto ds = std::make_shared<gaze::GazeDataset>();
  for (const char* name : {"TH34", "UH29"}) {
    o.participant = name;
    o.stimulus = "Europe";
    auto one = gaze::read_gaze_file(
        test::shared_data(std::string("gaze/andersson2017_lund/tsv/") + name + "_img_Europe.tsv").string(),
        o);
    for (auto& r : one.recordings) ds->recordings.push_back(std::move(r));
  }
  return ds;
}

const char* kFastParams = R"("params": {"size": 128, "iterations": 4, "h": 16, "spl": 4}, "backend": "cpu")";

class GazeViewsTest : public test_routes::RouteFixture {
 protected:
  GazeViewsTest() {
    open(one_flight());
    data = lund();
    app->gaze->put("lund", "test-admin", "plain", data);
  }
  void expect_detail(const Response& r, int status, const std::string& error, const std::string& param,
                     const std::string& detail) {
    expect_error(r, status, error, param);
    EXPECT_EQ(body(r)["detail"], detail);
  }
  std::shared_ptr<const gaze::GazeDataset> data;
};

TEST_F(GazeViewsTest, TileMatchesBinningOfTheSamples) {
  const Response r = get("/api/v1/gaze/lund/tiles/0/0/0.png");
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(r.content_type, "image/png");
  const density::Image img = density::decode_png(r.shared_body ? *r.shared_body : r.body);
  ASSERT_EQ(img.width, 256);
  // Binning here: 4 stimulus px per tile px (side 1024); the opaque pixels are the cells holding a valid
  // sample on the stimulus.
  std::set<std::pair<int, int>> cells;
  for (const auto& rec : data->recordings)
    for (std::size_t i = 0; i < rec.size(); ++i)
      if (rec.valid[i] && rec.x[i] >= 0 && rec.x[i] < 1024 && rec.y[i] >= 0 && rec.y[i] < 768)
        cells.insert({int(std::floor(rec.x[i] / 4)), int(std::floor(rec.y[i] / 4))});
  std::size_t opaque = 0;
  for (int j = 0; j < 256; ++j)
    for (int i = 0; i < 256; ++i) {
      const bool drawn = img.pixel(i, j)[3] != 0;
      opaque += drawn;
      if (drawn) ASSERT_TRUE(cells.count({i, j})) << i << "," << j;
    }
  EXPECT_EQ(opaque, cells.size());
  // One participant: fewer cells. And the ETag.
  const Response th = get("/api/v1/gaze/lund/tiles/0/0/0.png", {{"participant", "TH34"}});
  ASSERT_EQ(th.status, 200);
  const std::string etag = header(r, "ETag");
  ASSERT_FALSE(etag.empty());
  EXPECT_EQ(get("/api/v1/gaze/lund/tiles/0/0/0.png", {}, {{"if-none-match", etag}}).status, 304);
  // Fixations weighted by duration draw a different picture of the same extent.
  EXPECT_EQ(get("/api/v1/gaze/lund/tiles/1/1/0.png", {{"what", "fixations"}, {"kernel", "3"}}).status, 200);
}

TEST_F(GazeViewsTest, TileErrors) {
  expect_detail(get("/api/v1/gaze/lund/tiles/1/2/0.png"), 400, "invalid_argument", "x",
                "x must lie in 0..1, got 2");
  expect_error(get("/api/v1/gaze/lund/tiles/0/0/0.png", {{"what", "saccades"}}), 400, "invalid_argument",
               "what");
  expect_detail(get("/api/v1/gaze/lund/tiles/0/0/0.png", {{"what", "saccades"}}), 400, "invalid_argument",
                "what", "'saccades' is not samples or fixations");
  expect_error(get("/api/v1/gaze/lund/tiles/0/0/0.png", {{"participant", "nobody"}}), 400, "invalid_argument",
               "participant");
  expect_error(get("/api/v1/gaze/lund/tiles/0/0/0.png", {{"kernel", "40"}}), 400, "invalid_argument",
               "kernel");
  expect_detail(get("/api/v1/gaze/lund/tiles/0/0/0.png", {{"size", "512"}}), 400, "invalid_argument", "size",
                "size: gaze tiles are 256 px");
  expect_error(get("/api/v1/gaze/lund/tiles/0/0/0.png", {{"value", "count"}}), 400, "invalid_argument",
               "value");
  expect_error(get("/api/v1/gaze/nope/tiles/0/0/0.png"), 404, "not_found", "gaze");
}

TEST_F(GazeViewsTest, LegendSpansTheZoom) {
  expect_detail(get("/api/v1/gaze/lund/tiles/legend"), 400, "invalid_argument", "z",
                "z: the zoom of the tiles is required (?z=)");
  const Response r = get("/api/v1/gaze/lund/tiles/legend", {{"z", "0"}, {"stops", "3"}, {"how", "linear"}});
  ASSERT_EQ(r.status, 200) << r.body;
  const auto j = body(r);
  // The largest cell count, binned here.
  std::map<std::pair<int, int>, int> per;
  for (const auto& rec : data->recordings)
    for (std::size_t i = 0; i < rec.size(); ++i)
      if (rec.valid[i] && rec.x[i] >= 0 && rec.x[i] < 1024 && rec.y[i] >= 0 && rec.y[i] < 768)
        ++per[{int(std::floor(rec.x[i] / 4)), int(std::floor(rec.y[i] / 4))}];
  int hi = 0;
  for (const auto& [c, n] : per) hi = std::max(hi, n);
  EXPECT_EQ(j["hi"], double(hi));
  EXPECT_EQ(j["lo"], 1.0);
  EXPECT_EQ(j["stops"].size(), 3u);
  EXPECT_EQ(j["unit"], "samples per pixel");
  EXPECT_EQ(j["stimulus"]["width_px"], 1024.0);
}

TEST_F(GazeViewsTest, AoiAgainstBruteForce) {
  const std::string aois =
      R"("aois": [{"name": "left", "rect": [0, 0, 512, 768]}, {"name": "tri", "polygon": [[512, 0], [1024, 0], [1024, 768]]}])";
  const Response r =
      send("POST", "/api/v1/gaze/lund/aoi", "{" + std::string(aois) + R"(, "participant": "UH29"})");
  ASSERT_EQ(r.status, 200) << r.body;
  const auto j = body(r);
  // Brute force over the events route's own fixations of that participant.
  gaze::GazeFilter f;
  f.participant = "UH29";
  const gaze::EventList ev = gaze::list_events(*data, f, {}, {gaze::EventType::fixation}, 1000000);
  std::size_t left = 0, tri = 0, outside = 0;
  double dwell_left = 0;
  for (const auto& e : ev.events) {
    if (e.x >= 0 && e.x <= 512 && e.y >= 0 && e.y <= 768)
      ++left, dwell_left += e.t_end_ms - e.t_start_ms;
    else if (e.x <= 1024 && e.y >= 0 && e.y <= 1.5 * (e.x - 512))  // the triangle, below its diagonal
      ++tri;
    else
      ++outside;
  }
  EXPECT_EQ(j["recordings"], 1);
  EXPECT_EQ(j["fixations"], ev.events.size());
  EXPECT_EQ(j["aois"][0]["name"], "left");
  EXPECT_EQ(j["aois"][0]["fixations"], left);
  EXPECT_NEAR(j["aois"][0]["dwell_ms"].get<double>(), dwell_left, 1e-6);
  EXPECT_EQ(j["aois"][1]["fixations"], tri);
  EXPECT_EQ(j["outside"], outside);
  EXPECT_EQ(j["aois"][0]["visitors"], left ? 1 : 0);
  EXPECT_EQ(j["transitions"]["names"], nlohmann::json::parse(R"(["left","tri"])"));
  EXPECT_EQ(j["method"], "ivt");
}

TEST_F(GazeViewsTest, AoiErrors) {
  expect_detail(send("POST", "/api/v1/gaze/lund/aoi", "{}"), 400, "invalid_argument", "aois",
                "aois: give the areas of interest");
  expect_detail(send("POST", "/api/v1/gaze/lund/aoi", R"({"aois": [{"name": "a", "rect": [5, 0, 1, 1]}]})"),
                400, "invalid_argument", "aois", "AOI 0 (a): a rectangle needs x0 < x1 and y0 < y1");
  expect_error(
      send("POST", "/api/v1/gaze/lund/aoi", R"({"aois": [{"name": "a", "rect": [0, 0, 1, 1]}], "x": 1})"),
      400, "invalid_argument", "x");
  expect_error(send("POST", "/api/v1/gaze/lund/aoi",
                    R"({"aois": [{"name": "a", "rect": [0, 0, 1, 1]}], "method": "xyz"})"),
               400, "invalid_argument", "method");
  expect_error(send("POST", "/api/v1/gaze/lund/aoi",
                    R"({"aois": [{"name": "a", "rect": [0, 0, 1, 1]}], "velocity_threshold": -1})"),
               400, "invalid_argument", "velocity_threshold");
  expect_error(send("POST", "/api/v1/gaze/lund/aoi", "[1]"), 400, "invalid_argument", "body");
  expect_error(send("POST", "/api/v1/gaze/nope/aoi", R"({"aois": [{"name": "a", "rect": [0, 0, 1, 1]}]})"),
               404, "not_found", "gaze");
}

TEST_F(GazeViewsTest, BundleJobStoresABundle) {
  const Response r = send("POST", "/api/v1/gaze/lund/bundle",
                          std::string(R"({"participant": "TH34", )") + kFastParams + "}");
  ASSERT_EQ(r.status, 202) << r.body;
  const auto j = body(r);
  EXPECT_EQ(j["job"]["kind"], "bundle");
  const JobState done = app->jobs.wait(j["job"]["id"]);
  ASSERT_EQ(done.state, "done") << done.to_json().dump();
  const std::string bid = j["bundle"];
  const auto meta = body(get("/api/v1/bundles/" + bid));
  EXPECT_EQ(meta["units"], "plane");
  EXPECT_EQ(meta["source"]["gaze"], "lund");
  EXPECT_EQ(meta["source"]["filters"]["participant"], "TH34");
  gaze::GazeFilter f;
  f.participant = "TH34";
  const auto sac = gaze::list_events(*data, f, {}, {gaze::EventType::saccade}, 1000000).events;
  EXPECT_EQ(meta["source"]["saccades"], sac.size());
  // The polylines, back in stimulus px, start and end where the saccades do.
  const auto poly = body(get("/api/v1/bundles/" + bid + "/polylines", {{"relaxation", "0"}}));
  ASSERT_EQ(poly["polylines"].size(), sac.size());
  const auto& first = poly["polylines"][0];
  const auto& pts = first.contains("points") ? first["points"] : first;
  EXPECT_NEAR(pts[0][0].get<double>(), sac[0].x, 0.05);
  EXPECT_NEAR(pts[0][1].get<double>(), sac[0].y, 0.05);
  EXPECT_EQ(get("/api/v1/bundles/" + bid + "/image.png", {{"width", "256"}}).status, 200);
}

TEST_F(GazeViewsTest, BundleErrors) {
  expect_detail(send("POST", "/api/v1/gaze/lund/bundle", R"({"t0_ms": 1000000000})"), 422, "unprocessable",
                "stimulus", "no saccade to bundle in the selected recordings");
  expect_error(send("POST", "/api/v1/gaze/lund/bundle", R"({"params": {"iterations": 0}})"), 400,
               "invalid_argument", "iterations");
  expect_error(send("POST", "/api/v1/gaze/lund/bundle", R"({"params": 3})"), 400, "invalid_argument",
               "params");
  expect_error(send("POST", "/api/v1/gaze/lund/bundle", R"({"stimulus": "nowhere"})"), 400,
               "invalid_argument", "stimulus");
  expect_error(send("POST", "/api/v1/gaze/lund/bundle", R"({"backend": "gpu"})"), 400, "invalid_argument",
               "backend");
  expect_error(send("POST", "/api/v1/gaze/nope/bundle", "{}"), 404, "not_found", "gaze");
}

}  // namespace
}  // namespace trailscope::server
