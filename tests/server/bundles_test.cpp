// Bundling over the API, in process: graph uploads, bundle jobs of a graph and of a dataset window, the
// meta, image, polylines (JSON and TSBL) and tiles of a result, exact error statuses and details,
// persistence across a store reopen, eviction beyond kMaxStoredBundles, and cancellation.
#include <cmath>
#include <cstring>
#include <fstream>

#include <gtest/gtest.h>

#include "route_fixture.hpp"
#include "formats/bundle_export.hpp"
#include "trailscope/density/png.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::server {
namespace {

/// Ten flights from Amsterdam towards Frankfurt, fanned out by 0.05° of latitude, one sample a minute
/// from 2018-01-01T00:00Z for an hour.
std::shared_ptr<Dataset> corridor(const std::string& id) {
  TrailSetBuilder b;
  for (int f = 0; f < 10; ++f)
    for (int i = 0; i <= 60; ++i) {
      Sample s;
      s.t = 1514764800.0 + i * 60, s.lat = 52.3f - i * 0.035f + f * 0.05f, s.lon = 4.76f + i * 0.06f;
      s.alt = 10000, s.speed = 220;
      char icao[7];
      std::snprintf(icao, sizeof icao, "4ca1%02d", f);
      b.add(icao, "KLM" + std::to_string(f), s);
    }
  auto ds = std::make_shared<Dataset>();
  ds->id = id, ds->name = id, ds->format = "test", ds->created = "2026-01-01T00:00:00Z";
  ds->trails = std::make_shared<const TrailSet>(b.build());
  return ds;
}

/// Small and fast: every test bundle runs on the C++ reference in a 128 px image.
const char* kFastParams = R"("params": {"size": 128, "iterations": 4, "h": 16, "spl": 4}, "backend": "cpu")";

class BundlesTest : public test_routes::RouteFixture {
 protected:
  BundlesTest() {
    open(corridor("nl"));
    store->put(corridor("other"));
  }
  /// Uploads test_routes::two_clusters() and returns the graph id.
  std::string upload_graph() {
    const Response r = send("POST", "/api/v1/graphs", test_routes::two_clusters(), {{"name", "clusters"}});
    EXPECT_EQ(r.status, 201) << r.body;
    return body(r).at("id");
  }
  /// POSTs a bundle body, waits for its job and returns the bundle id (expects "done").
  std::string bundle(const std::string& json) {
    const Response r = send("POST", "/api/v1/bundles", json);
    EXPECT_EQ(r.status, 202) << r.body;
    if (r.status != 202) return "";
    const auto j = body(r);
    EXPECT_EQ(header(r, "Location"), "/api/v1/jobs/" + j["job"]["id"].get<std::string>());
    EXPECT_EQ(j["job"]["kind"], "bundle");
    const JobState done = app->jobs.wait(j["job"]["id"]);
    EXPECT_EQ(done.state, "done") << done.to_json().dump();
    EXPECT_EQ(done.result["id"], j["bundle"]);
    return j["bundle"];
  }
  static void expect_detail(const Response& r, int status, const std::string& error, const std::string& param,
                            const std::string& detail) {
    expect_error(r, status, error, param);
    EXPECT_EQ(body(r)["detail"], detail);
  }
};

TEST_F(BundlesTest, GraphUploadListGetDelete) {
  const Response r = send("POST", "/api/v1/graphs", test_routes::two_clusters(), {{"name", "clusters"}});
  ASSERT_EQ(r.status, 201) << r.body;
  const auto g = body(r);
  EXPECT_EQ(g["id"], "g1");
  EXPECT_EQ(header(r, "Location"), "/api/v1/graphs/g1");
  EXPECT_EQ(g["name"], "clusters");
  EXPECT_EQ(g["format"], "node_link");
  EXPECT_EQ(g["edges"], 16);
  EXPECT_EQ(g["points"], 32);
  EXPECT_EQ(g["nodes"], 8);
  EXPECT_EQ(g["geographic"], false);
  EXPECT_EQ(g["bbox"], nlohmann::json({0.0, 0.0, 100.0, 35.0}));
  EXPECT_EQ(body(get("/api/v1/graphs"))["graphs"].size(), 1u);
  EXPECT_EQ(body(get("/api/v1/graphs/g1"))["edges"], 16);
  EXPECT_EQ(send("DELETE", "/api/v1/graphs/g1").status, 204);
  expect_detail(get("/api/v1/graphs/g1"), 404, "not_found", "graph", "graph 'g1' does not exist");
  expect_detail(send("DELETE", "/api/v1/graphs/g1"), 404, "not_found", "graph", "graph 'g1' does not exist");
}

TEST_F(BundlesTest, OdCsvByNameAsJson) {
  const nlohmann::json upload = {
      {"edges_csv", "origin,destination,count\nAMS,FRA,3\nAMS,LHR,2\nFRA,LHR,1\n"},
      {"nodes_csv",
       "iata,name,latitude,longitude\nAMS,Schiphol,52.31,4.76\nFRA,Frankfurt,50.03,8.56\n"
       "LHR,Heathrow,51.47,-0.45\n"}};
  const Response r = send("POST", "/api/v1/graphs", upload.dump(), {},
                          {{"content-type", "application/json; charset=utf-8"}});
  ASSERT_EQ(r.status, 201) << r.body;
  EXPECT_EQ(body(r)["format"], "od_csv");
  EXPECT_EQ(body(r)["edges"], 3);
  EXPECT_EQ(body(r)["geographic"], true);
  EXPECT_EQ(body(r)["units"], "epsg3857");
  // A geographic graph's polylines come back in lon/lat.
  const std::string id = bundle(R"({"source": {"graph": "g1"}, )" + std::string(kFastParams) + "}");
  const auto j = body(get("/api/v1/bundles/" + id + "/polylines", {{"relaxation", "1"}}));
  EXPECT_EQ(j["coordinates"], "lonlat");
  ASSERT_EQ(j["polylines"].size(), 3u);
  EXPECT_NEAR(j["polylines"][0][0][0].get<double>(), 4.76, 1e-3);
  EXPECT_NEAR(j["polylines"][0][0][1].get<double>(), 52.31, 1e-3);
  // Unknown fields of the OD form are named.
  const Response bad = send("POST", "/api/v1/graphs", R"({"edges_csv": "a,b\n", "nodes": "x"})", {},
                            {{"content-type", "application/json"}});
  expect_detail(bad, 400, "invalid_argument", "nodes",
                "unknown field 'nodes' (an OD upload has edges_csv and nodes_csv)");
}

TEST_F(BundlesTest, BundleOfAGraph) {
  const std::string g = upload_graph();
  const std::string id = bundle(R"({"source": {"graph": ")" + g + R"("}, )" + kFastParams + "}");
  EXPECT_EQ(id, "b1");

  const auto meta = body(get("/api/v1/bundles/b1"));
  EXPECT_EQ(meta["id"], "b1");
  EXPECT_EQ(meta["source"]["graph"], g);
  EXPECT_EQ(meta["source"]["name"], "clusters");
  EXPECT_EQ(meta["units"], "plane");
  EXPECT_EQ(meta["coordinates"], "source");
  EXPECT_EQ(meta["polylines"], 16);
  EXPECT_EQ(meta["input_points"], 32);
  EXPECT_GT(meta["points"].get<int>(), 32);
  EXPECT_EQ(meta["params"]["size"], "128");
  EXPECT_EQ(meta["params"]["iterations"], "4");
  EXPECT_EQ(meta["path"], "cpu");
  for (const char* k :
       {"ink_raw_px", "ink_bundled_px", "ink_reduction", "mean_displacement_px", "max_displacement_px"})
    EXPECT_TRUE(meta["quality"].contains(k)) << k;
  EXPECT_GT(meta["quality"]["ink_raw_px"].get<double>(), 0);
  EXPECT_GT(meta["quality"]["mean_displacement_px"].get<double>(), 0);  // the edges moved
  for (const char* k : {"resample", "splat", "convolve", "advect", "smooth", "endpoints", "post", "total"})
    EXPECT_TRUE(meta["times_ms"].contains(k)) << k;
  const auto list = body(get("/api/v1/bundles"));
  ASSERT_EQ(list["bundles"].size(), 1u);
  EXPECT_EQ(list["bundles"][0], meta);

  // The image: a PNG of the asked size, the same bytes again (cache), 304 on its ETag.
  Response img = get("/api/v1/bundles/b1/image.png", {{"width", "64"}, {"style", "lines"}});
  ASSERT_EQ(img.status, 200) << img.body;
  EXPECT_EQ(img.content_type, "image/png");
  const density::Image decoded = density::decode_png(img.bytes());
  EXPECT_EQ(decoded.width, 64);
  EXPECT_EQ(decoded.height, 64);  // a fitted graph's frame is square
  const std::string etag = header(img, "ETag");
  EXPECT_EQ(header(img, "Cache-Control"), "public, max-age=300");
  EXPECT_EQ(get("/api/v1/bundles/b1/image.png", {{"width", "64"}, {"style", "lines"}}).bytes(), img.bytes());
  EXPECT_EQ(
      get("/api/v1/bundles/b1/image.png", {{"width", "64"}, {"style", "lines"}}, {{"if-none-match", etag}})
          .status,
      304);

  // Polylines, relaxed fully: every point lies on its straight input edge, the ends on the nodes.
  auto j = body(get("/api/v1/bundles/b1/polylines", {{"relaxation", "1"}}));
  EXPECT_EQ(j["bundle"], "b1");
  EXPECT_EQ(j["coordinates"], "source");
  EXPECT_EQ(j["relaxation"], 1.0);
  ASSERT_EQ(j["polylines"].size(), 16u);
  for (const auto& line : j["polylines"]) {
    const double x0 = line.front()[0], y0 = line.front()[1], x1 = line.back()[0], y1 = line.back()[1];
    EXPECT_NEAR(x0, 0.0, 1e-3);
    EXPECT_NEAR(x1, 100.0, 1e-3);
    for (const auto& p : line) {
      const double cross = (x1 - x0) * (p[1].get<double>() - y0) - (y1 - y0) * (p[0].get<double>() - x0);
      EXPECT_NEAR(cross / std::hypot(x1 - x0, y1 - y0), 0.0, 1e-2);
    }
  }
  // Bundled (relaxation 0): some interior point has left its straight edge.
  j = body(get("/api/v1/bundles/b1/polylines", {{"relaxation", "0"}}));
  double moved = 0;
  for (const auto& line : j["polylines"]) {
    const double x0 = line.front()[0], y0 = line.front()[1], x1 = line.back()[0], y1 = line.back()[1];
    for (const auto& p : line)
      moved = std::max(
          moved, std::fabs((x1 - x0) * (p[1].get<double>() - y0) - (y1 - y0) * (p[0].get<double>() - x0)) /
                     std::hypot(x1 - x0, y1 - y0));
  }
  EXPECT_GT(moved, 0.5);

  // TSBL: header, sections and sizes as documented; the bundled points equal the JSON's.
  const Response bin = get("/api/v1/bundles/b1/polylines", {{"format", "binary"}, {"relaxation", "0"}});
  ASSERT_EQ(bin.status, 200);
  EXPECT_EQ(bin.content_type, "application/octet-stream");
  const std::string& s = bin.bytes();
  const auto u32 = [&](std::size_t off) {
    std::uint32_t v;
    std::memcpy(&v, s.data() + off, 4);
    return v;
  };
  const auto f32 = [&](std::size_t off) {
    float v;
    std::memcpy(&v, s.data() + off, 4);
    return v;
  };
  ASSERT_GE(s.size(), 32u);
  EXPECT_EQ(s.substr(0, 4), "TSBL");
  EXPECT_EQ(u32(4), 1u);
  EXPECT_EQ(u32(8), 0u);  // source units
  const std::uint32_t n = u32(12), m = u32(16);
  EXPECT_EQ(n, 16u);
  EXPECT_EQ(m, meta["points"].get<std::uint32_t>());
  EXPECT_EQ(f32(20), 0.0f);
  EXPECT_EQ(f32(24), 0.2f);  // max_displacement's default
  EXPECT_EQ(s.size(), 32 + 4 * (n + 1) + 16 * m + 4 * n);
  EXPECT_EQ(u32(32), 0u);
  EXPECT_EQ(u32(32 + 4 * n), m);
  const std::size_t xy = 32 + 4 * (n + 1);
  EXPECT_FLOAT_EQ(f32(xy + 8), j["polylines"][0][1][0].get<float>());
  EXPECT_FLOAT_EQ(f32(xy + 12), j["polylines"][0][1][1].get<float>());
  // The original section starts on an edge's first node; lengths are ~100 source units (a 100-wide graph).
  EXPECT_NEAR(f32(xy + 8 * m), 0.0f, 1e-3);
  EXPECT_NEAR(f32(xy + 16 * m), 100.0f, 1.0f);

  // A graph bundle has no map tiles.
  expect_detail(get("/tiles/nl/bundle/b1/0/0/0.png"), 404, "not_found", "bundle",
                "bundle 'b1' is not a bundle of dataset 'nl'");

  EXPECT_EQ(send("DELETE", "/api/v1/bundles/b1").status, 204);
  expect_detail(get("/api/v1/bundles/b1"), 404, "not_found", "bundle", "bundle 'b1' does not exist");
  expect_detail(get("/api/v1/bundles/b1/image.png"), 404, "not_found", "bundle",
                "bundle 'b1' does not exist");
  EXPECT_EQ(body(get("/api/v1/bundles"))["bundles"].size(), 0u);
}

// z = 6 tile holding Amsterdam (lon 4.76, lat 52.3): x = 32, y = 21.
TEST_F(BundlesTest, BundleOfADatasetWindow) {
  const std::string id = bundle(
      R"({"source": {"dataset": "nl", "query": {"t0": "2018-01-01T00:10:00Z", "t1": 1514767200, "alt_unit": "m"}}, )" +
      std::string(kFastParams) + "}");
  const auto meta = body(get("/api/v1/bundles/" + id));
  EXPECT_EQ(meta["source"]["dataset"], "nl");
  EXPECT_EQ(meta["source"]["query"]["t1"], "1514767200");
  EXPECT_EQ(meta["source"]["canonical"], "t0=1514765400&t1=1514767200");
  EXPECT_EQ(meta["source"]["max_gap"], nullptr);
  EXPECT_EQ(meta["units"], "merc32");
  EXPECT_EQ(meta["coordinates"], "lonlat");
  EXPECT_EQ(meta["polylines"], 10);
  EXPECT_EQ(meta["input_points"], 10 * 30);  // samples 10..39 of each flight

  // Relaxed fully, the first point is the first sample in the window (i = 10) of the first flight.
  const auto j = body(get("/api/v1/bundles/" + id + "/polylines", {{"relaxation", "1"}}));
  EXPECT_EQ(j["coordinates"], "lonlat");
  ASSERT_EQ(j["polylines"].size(), 10u);
  bool found = false;
  for (const auto& line : j["polylines"])
    found |= std::fabs(line[0][0].get<double>() - (4.76 + 10 * 0.06)) < 1e-3 &&
             std::fabs(line[0][1].get<double>() - (52.3 - 10 * 0.035)) < 1e-3;
  EXPECT_TRUE(found) << j["polylines"][0][0].dump();

  // TSBL in lon/lat: flag bit 0, lengths in Mercator degrees (an hour's leg is ~1.7° of longitude).
  const Response bin = get("/api/v1/bundles/" + id + "/polylines", {{"format", "binary"}});
  const std::string& s = bin.bytes();
  std::uint32_t flags, n, m;
  std::memcpy(&flags, s.data() + 8, 4), std::memcpy(&n, s.data() + 12, 4), std::memcpy(&m, s.data() + 16, 4);
  EXPECT_EQ(flags, 1u);
  float len0;
  std::memcpy(&len0, s.data() + 32 + 4 * (n + 1) + 16 * m, 4);
  EXPECT_GT(len0, 1.5f);
  EXPECT_LT(len0, 4.0f);

  // Map tiles: PNG with ETag and 304; lines where the flights are, transparent elsewhere.
  const std::string tile = "/tiles/nl/bundle/" + id + "/6/32/21.png";
  const Response t = get(tile);
  ASSERT_EQ(t.status, 200) << t.body;
  EXPECT_EQ(t.content_type, "image/png");
  const density::Image img = density::decode_png(t.bytes());
  EXPECT_EQ(img.width, 256);
  int opaque = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) opaque += img.pixel(x, y)[3] > 0;
  EXPECT_GT(opaque, 50);
  EXPECT_LT(opaque, 256 * 256 / 4);
  EXPECT_EQ(get(tile, {}, {{"if-none-match", header(t, "ETag")}}).status, 304);
  EXPECT_EQ(density::decode_png(get(tile, {{"size", "512"}}).bytes()).width, 512);
  // A tile far from the data is empty.
  const density::Image far = density::decode_png(get("/tiles/nl/bundle/" + id + "/6/0/0.png").bytes());
  bool any = false;
  for (std::size_t i = 3; i < far.rgba.size(); i += 4) any |= far.rgba[i] > 0;
  EXPECT_FALSE(any);

  expect_detail(get("/tiles/other/bundle/" + id + "/6/32/21.png"), 404, "not_found", "bundle",
                "bundle '" + id + "' is not a bundle of dataset 'other'");
  expect_error(get("/tiles/nope/bundle/" + id + "/6/32/21.png"), 404, "not_found", "dataset");
  expect_detail(get("/tiles/nl/bundle/b99/6/32/21.png"), 404, "not_found", "bundle",
                "bundle 'b99' does not exist");
  expect_error(get(tile, {{"size", "300"}}), 400, "invalid_argument", "size");
  expect_error(get("/tiles/nl/bundle/" + id + "/6/64/21.png"), 400, "invalid_argument", "x");
  expect_detail(get(tile, {{"value", "count"}}), 400, "invalid_argument", "value",
                "unknown query parameter 'value'");
  expect_error(get(tile, {{"style", "wavy"}}), 400, "invalid_argument", "style");

  // The colour modes the dashboard offers (its legend per mode, web/src/lib/legend.ts): the same pixels
  // drawn with the same alpha, other colours; flat is grey everywhere.
  for (const std::string color : {"direction", "density", "displacement", "flat"}) {
    SCOPED_TRACE(color);
    const Response r = get(tile, {{"color", color}});
    ASSERT_EQ(r.status, 200) << r.body;
    EXPECT_NE(r.bytes(), t.bytes());
    const density::Image c = density::decode_png(r.bytes());
    ASSERT_EQ(c.rgba.size(), img.rgba.size());
    bool grey = true;
    for (std::size_t i = 0; i < c.rgba.size(); i += 4) {
      ASSERT_EQ(c.rgba[i + 3], img.rgba[i + 3]) << "pixel " << i / 4;
      if (c.rgba[i + 3] > 0) grey &= c.rgba[i] == c.rgba[i + 1] && c.rgba[i + 1] == c.rgba[i + 2];
    }
    EXPECT_EQ(grey, color == "flat");
  }
  expect_detail(get(tile, {{"color", "hue"}}), 400, "invalid_argument", "color",
                "color 'hue' is not one of length, direction, density, displacement, flat");
}

TEST_F(BundlesTest, RequestErrorsNameTheField) {
  const auto post = [&](const std::string& b) { return send("POST", "/api/v1/bundles", b); };
  const std::string need_object = "body: a JSON object {\"source\": ..., \"params\": ...} is required";
  expect_detail(post(""), 400, "invalid_argument", "body", need_object);
  expect_detail(post("{nope"), 400, "invalid_argument", "body", need_object);
  expect_detail(post("[1]"), 400, "invalid_argument", "body", need_object);
  expect_detail(post(R"({"source": {"dataset": "nl"}, "colour": 1})"), 400, "invalid_argument", "colour",
                "unknown field 'colour' in the body");
  expect_detail(post(R"({"params": {}})"), 400, "invalid_argument", "source",
                "source: an object {\"dataset\": ..., \"query\": ...} or {\"graph\": ...} is required");
  expect_detail(post(R"({"source": {"dataset": "nl", "graph": "g1"}})"), 400, "invalid_argument", "source",
                "source: give either \"dataset\" or \"graph\", not both or neither");
  expect_detail(post(R"({"source": {"dataset": "nl", "window": 1}})"), 400, "invalid_argument", "window",
                "unknown field 'window' in source");
  expect_detail(post(R"({"source": {"dataset": "nl", "query": {"t_0": "1"}}})"), 400, "invalid_argument",
                "t_0", "unknown query parameter 't_0'");
  expect_error(post(R"({"source": {"dataset": "nl", "query": {"t0": "soon"}}})"), 400, "invalid_argument",
               "t0");
  expect_detail(post(R"({"source": {"dataset": "nl", "max_gap": -5}})"), 400, "invalid_argument", "max_gap",
                "max_gap: must be a positive number of seconds");
  expect_detail(post(R"({"source": {"graph": "g1", "max_gap": 5}})"), 400, "invalid_argument", "source",
                "source: query and max_gap apply to a dataset, not to a graph");
  expect_error(post(R"({"source": {"dataset": "nl"}, "params": {"h": 1}})"), 400, "invalid_argument", "h");
  expect_error(post(R"({"source": {"dataset": "nl"}, "params": {"profile": "round"}})"), 400,
               "invalid_argument", "profile");
  expect_error(post(R"({"source": {"dataset": "nl"}, "params": {"nope": 1}})"), 400, "invalid_argument",
               "nope");
  expect_detail(post(R"({"source": {"dataset": "nl"}, "params": {"h": [1]}})"), 400, "invalid_argument", "h",
                "h: must be a string, a number or a boolean");
  expect_error(post(R"({"source": {"dataset": "nl"}, "backend": "gpu"})"), 400, "invalid_argument",
               "backend");
  expect_detail(post(R"({"source": {"dataset": "nope"}})"), 404, "not_found", "dataset",
                "dataset 'nope' does not exist");
  expect_detail(post(R"({"source": {"graph": "g99"}})"), 404, "not_found", "graph",
                "graph 'g99' does not exist");
  // A window without flights is refused before a job starts.
  expect_error(post(R"({"source": {"dataset": "nl", "query": {"t0": "2019-01-01T00:00:00Z"}}})"), 422,
               "unprocessable", "query");
  EXPECT_TRUE(app->jobs.list().empty());

  expect_detail(get("/api/v1/bundles/b99"), 404, "not_found", "bundle", "bundle 'b99' does not exist");
  expect_detail(send("DELETE", "/api/v1/bundles/b99"), 404, "not_found", "bundle",
                "bundle 'b99' does not exist");
  expect_detail(get("/api/v1/bundles/b99/polylines"), 404, "not_found", "bundle",
                "bundle 'b99' does not exist");
  expect_detail(get("/api/v1/bundles", {{"page", "1"}}), 400, "invalid_argument", "page",
                "unknown query parameter 'page'");

  const std::string id = bundle(R"({"source": {"dataset": "nl"}, )" + std::string(kFastParams) + "}");
  const std::string p = "/api/v1/bundles/" + id;
  expect_detail(get(p + "/polylines", {{"format", "xml"}}), 400, "invalid_argument", "format",
                "format must be json or binary, got 'xml'");
  expect_detail(get(p + "/polylines", {{"relaxation", "2"}}), 400, "invalid_argument", "relaxation",
                "relaxation must lie in 0..1, got 2");
  expect_detail(get(p + "/polylines", {{"relaxation", "x"}}), 400, "invalid_argument", "relaxation",
                "relaxation: 'x' is not a number");
  expect_error(get(p + "/image.png", {{"width", "9000"}}), 400, "invalid_argument", "width");
  expect_error(get(p + "/image.png", {{"cmap", "rainbowz"}}), 400, "invalid_argument", "cmap");
  expect_detail(get(p + "/image.png", {{"size", "256"}}), 400, "invalid_argument", "size",
                "unknown query parameter 'size'");
}

TEST_F(BundlesTest, GraphUploadErrors) {
  expect_detail(send("POST", "/api/v1/graphs", ""), 400, "invalid_argument", "body",
                "body: the upload is empty");
  expect_error(send("POST", "/api/v1/graphs", "\x89PNG\r\n\x1a\n not a graph"), 415, "unsupported_format",
               "input");
  expect_error(send("POST", "/api/v1/graphs", test_routes::two_clusters(), {{"format", "xml"}}), 400,
               "invalid_argument", "format");
  expect_error(send("POST", "/api/v1/graphs", R"({"nodes": [], "links": []})"), 422, "unprocessable",
               "input");
  expect_detail(send("POST", "/api/v1/graphs", test_routes::two_clusters(), {{"name", ""}}), 400,
                "invalid_argument", "name", "name: 1 to 128 characters");
  expect_detail(send("POST", "/api/v1/graphs", test_routes::two_clusters(), {{"id", "x"}}), 400,
                "invalid_argument", "id", "unknown query parameter 'id'");
  // A streamed upload over kMaxGraphUploadBytes (a sparse file: no disk is written), removed afterwards.
  Request r;
  r.method = "POST", r.path = "/api/v1/graphs";
  r.body_file = store->upload_dir() / "big-upload";
  { std::ofstream(r.body_file) << "x"; }
  std::filesystem::resize_file(r.body_file, limits::kMaxGraphUploadBytes + 1);
  expect_detail(router.handle(r), 413, "payload_too_large", "body",
                "graph upload exceeds the limit of 256 MiB");
  EXPECT_FALSE(std::filesystem::exists(r.body_file));
  EXPECT_EQ(body(get("/api/v1/graphs"))["graphs"].size(), 0u);
}

TEST_F(BundlesTest, BundlesAndGraphsSurviveAReopen) {
  upload_graph();
  const std::string id = bundle(R"({"source": {"graph": "g1"}, )" + std::string(kFastParams) + "}");
  const auto before = app->bundles->get(id);
  const std::string png = get("/api/v1/bundles/" + id + "/image.png", {{"width", "64"}}).bytes();

  BundleStore reopened(tmp.path() / "store");
  ASSERT_EQ(reopened.size(), 1u);
  EXPECT_EQ(reopened.meta(id), before->to_json());
  const auto after = reopened.get(id);
  EXPECT_EQ(after->bundled.lines.x, before->bundled.lines.x);  // float32-rounded both times: identical
  EXPECT_EQ(after->bundled.lines.y, before->bundled.lines.y);
  EXPECT_EQ(after->bundled.lines.offsets, before->bundled.lines.offsets);
  EXPECT_EQ(after->bundled.original.x, before->bundled.original.x);
  EXPECT_EQ(after->bundled.t, before->bundled.t);
  EXPECT_EQ(after->bundled.length, before->bundled.length);
  EXPECT_EQ(after->bundled.params.to_map(), before->bundled.params.to_map());
  EXPECT_EQ(reopened.reserve_id(), "b2");  // ids go on after the highest stored

  GraphStore graphs(tmp.path() / "store");
  ASSERT_EQ(graphs.list().size(), 1u);
  EXPECT_EQ(graphs.get("g1")->graph.edges.x, app->graphs->get("g1")->graph.edges.x);
  EXPECT_EQ(graphs.meta("g1"), body(get("/api/v1/graphs/g1")));

  // A whole new app over the same folder serves the same image bytes.
  app = std::make_unique<App>(store, store->upload_dir(), std::filesystem::path(), limits::kTileCacheBytes,
                              tmp.path() / "store");
  router = make_router(*app);
  EXPECT_EQ(get("/api/v1/bundles/" + id + "/image.png", {{"width", "64"}}).bytes(), png);
  // A folder without its manifest (a write cut short) is not a bundle.
  std::filesystem::create_directories(tmp.path() / "store" / "bundles" / "b7");
  EXPECT_EQ(BundleStore(tmp.path() / "store").size(), 1u);
}

TEST_F(BundlesTest, OldestBundlesAreEvicted) {
  BundleStore bs(tmp.path() / "evict");
  const auto one = [&] {
    auto b = std::make_shared<StoredBundle>();
    b->id = bs.reserve_id();
    b->created = "2026-01-01T00:00:00Z";
    b->source = {{"graph", "g1"}};
    b->bundled.lines.add_edge(0, 0, 1, 1);
    b->bundled.original = b->bundled.lines;
    b->bundled.t = {0, 1}, b->bundled.displacement = {0, 0}, b->bundled.length = {1.4f},
    b->bundled.angle = {0.7f};
    return b;
  };
  for (std::size_t i = 0; i < limits::kMaxStoredBundles; ++i) EXPECT_TRUE(bs.put(one()).empty());
  EXPECT_EQ(bs.size(), limits::kMaxStoredBundles);
  EXPECT_EQ(bs.put(one()), std::vector<std::string>{"b1"});
  EXPECT_EQ(bs.size(), limits::kMaxStoredBundles);
  EXPECT_THROW(bs.meta("b1"), Error);
  EXPECT_FALSE(std::filesystem::exists(tmp.path() / "evict" / "bundles" / "b1"));
  EXPECT_EQ(bs.list().front()["id"], "b2");
  EXPECT_EQ(bs.list().back()["id"], "b101");
}

TEST_F(BundlesTest, CancelledJobsStoreNothing) {
  // A long bundle (a large image, many iterations) and a second one queued behind it (one job worker):
  // both are cancelled, the first while it runs, the second before it starts.
  const std::string slow =
      R"({"source": {"dataset": "nl"}, "params": {"size": 4096, "iterations": 100, "spl": 1}, "backend": "cpu"})";
  const auto first = body(send("POST", "/api/v1/bundles", slow));
  const auto second = body(send("POST", "/api/v1/bundles", slow));
  for (const auto& j : {first, second}) {
    const Response r = send("DELETE", "/api/v1/jobs/" + j["job"]["id"].get<std::string>());
    EXPECT_EQ(r.status, 200);
  }
  for (const auto& j : {first, second}) {
    EXPECT_EQ(app->jobs.wait(j["job"]["id"]).state, "cancelled");
    expect_error(get("/api/v1/bundles/" + j["bundle"].get<std::string>()), 404, "not_found", "bundle");
  }
  EXPECT_EQ(app->bundles->size(), 0u);
}

// Garbage in every parameter of every bundle read route: a 2xx/304 or a 4xx with a JSON error body, never a
// 5xx and never an exception out of the router.
TEST_F(BundlesTest, GarbageParametersNeverGiveServerErrors) {
  const std::string id = bundle(R"({"source": {"dataset": "nl"}, )" + std::string(kFastParams) + "}");
  const std::vector<std::string> paths = {
      "/api/v1/bundles/" + id + "/image.png", "/api/v1/bundles/" + id + "/polylines",
      "/tiles/nl/bundle/" + id + "/6/32/21.png", "/api/v1/bundles/" + id, "/api/v1/bundles/params"};
  const std::vector<std::string> keys = {"width",
                                         "height",
                                         "style",
                                         "color",
                                         "alpha_mode",
                                         "alpha",
                                         "alpha_by_density",
                                         "shading_radius",
                                         "local_max_radius",
                                         "line_width",
                                         "cmap",
                                         "background",
                                         "relaxation",
                                         "size",
                                         "format"};
  const std::vector<std::string> values = garbage_values({"0.5", "16", "binary", "tube"});
  const int checked = expect_no_server_errors(paths, keys, values, 60, 3, 11, [](auto& q) {
    // Small images only: a valid 8192 px request is legal but slow, and not what this test is about.
    if (q.count("width")) q["width"] = q["width"].size() > 4 ? q["width"] : "-3";
    if (q.count("height")) q["height"] = q["height"].size() > 4 ? q["height"] : "-3";
  });
  EXPECT_EQ(checked, 60 * static_cast<int>(paths.size()));
}

TEST_F(BundlesTest, ParameterList) {
  const auto j = body(get("/api/v1/bundles/params"));
  ASSERT_EQ(j["params"].size(), bundling::parameter_infos().size());
  EXPECT_EQ(j["params"][0]["name"], bundling::parameter_infos()[0].name);
  bool has_h = false;
  for (const auto& p : j["params"])
    if (p["name"] == "h") {
      has_h = true;
      EXPECT_EQ(p["default"], "32");
      EXPECT_EQ(p["type"], "number");
    }
  EXPECT_TRUE(has_h);
  EXPECT_EQ(j["render"].size(), 11u);
}

}  // namespace
}  // namespace trailscope::server
