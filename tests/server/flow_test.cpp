// The flow routes (routes/flow.cpp) over the real compute path: the PNG and the JSON against
// flow::flow_image called directly, the ETag, the uploaded field, the flow tiles (against the route's JSON
// lines drawn independently, and the map computed once for all tiles), and every error with its exact
// status, kind, parameter and detail.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <thread>

#include "route_fixture.hpp"
#include "trailscope/density/png.hpp"
#include "trailscope/flow/render.hpp"
#include "trailscope/geo/web_mercator.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::server {
namespace {

constexpr double kT = 1514764800.0;

class FlowRouteTest : public test_routes::RouteFixture {
 protected:
  FlowRouteTest() {
    TrailSetBuilder b;
    // Forty flights east along 48..49.2°N, forty west a little south, twenty north across them: flows
    // that a single averaged field would partly cancel.
    for (int f = 0; f < 100; ++f) {
      char id[8];
      std::snprintf(id, sizeof id, "%06x", 0x300000 + f);
      for (int k = 0; k <= 40; ++k) {
        Sample s;
        s.t = kT + 60.0 * (f + k), s.alt = 10000;
        if (f < 40)
          s.lat = 48 + 0.03f * f, s.lon = 0 + 0.25f * k;
        else if (f < 80)
          s.lat = 47.99f + 0.03f * (f - 40), s.lon = 10 - 0.25f * k;
        else
          s.lat = 45 + 0.2f * k, s.lon = 3 + 0.05f * (f - 80);
        b.add(id, "FLW" + std::to_string(f), s);
      }
    }
    trails = std::make_shared<const TrailSet>(b.build());
    auto ds = std::make_shared<Dataset>();
    ds->id = "fl", ds->name = "fl", ds->format = "test", ds->created = "2026-01-01T00:00:00Z";
    ds->trails = trails;
    open(ds);
  }
  static void expect_bad(const Response& r, int status, const std::string& error, const std::string& param,
                         const std::string& detail) {
    expect_error(r, status, error, param);
    EXPECT_EQ(body(r).at("detail"), detail) << r.body;
  }
  static flow::FlowParams small() {
    flow::FlowParams p;
    p.field.grid = 64;
    return p;
  }
  std::shared_ptr<const TrailSet> trails;
};

constexpr const char* kPath = "/api/v1/datasets/fl/flow";

TEST_F(FlowRouteTest, PngIsTheComputeResultWithEtag) {
  const Response r = get(kPath, {{"grid", "64"}, {"level", "1.5"}, {"bbox", "-2,44,12,54"}});
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(r.content_type, "image/png");
  flow::FlowRenderParams rp;
  rp.level = 1.5;
  Query q;
  q.bbox = BBox{-2, 44, 12, 54};
  const flow::FlowImage direct = flow::flow_image(*trails, q, small(), rp, default_backend());
  EXPECT_EQ(r.bytes(), density::encode_png(direct.image));
  EXPECT_GT(direct.map.lines.size(), 4u);
  const std::string etag = header(r, "ETag");
  EXPECT_FALSE(etag.empty());
  EXPECT_EQ(get(kPath, {{"grid", "64"}, {"level", "1.5"}, {"bbox", "-2,44,12,54"}}, {{"if-none-match", etag}})
                .status,
            304);
  EXPECT_NE(header(get(kPath, {{"grid", "64"}, {"level", "1"}, {"bbox", "-2,44,12,54"}}), "ETag"), etag);
}

TEST_F(FlowRouteTest, JsonListsTheStreamlinesWithTheirSectors) {
  const Response r = get(kPath, {{"grid", "64"}, {"format", "json"}, {"level", "1"}});
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(r.content_type, "application/json");
  const auto j = body(r);
  flow::FlowRenderParams rp;
  rp.level = 1;
  const flow::FlowImage direct = flow::flow_image(*trails, Query{}, small(), rp, default_backend());
  const nlohmann::json expect = flow::flow_json(direct.map, 1);
  EXPECT_EQ(j.at("lines"), expect.at("lines"));
  EXPECT_EQ(j.at("sectors"), 8);
  EXPECT_EQ(j.at("width"), direct.image.width);
  // East-, west- and north-bound lines each exist: opposing flows did not cancel.
  std::set<int> sectors;
  for (const auto& l : j.at("lines")) sectors.insert(l.at("sector").get<int>());
  EXPECT_TRUE(sectors.count(2)) << "east";
  EXPECT_TRUE(sectors.count(6)) << "west";
  EXPECT_TRUE(sectors.count(0)) << "north";
  // Points are longitude/latitude inside the data.
  for (const auto& l : j.at("lines"))
    for (const auto& p : l.at("points")) {
      EXPECT_GE(p[0].get<double>(), -0.5);
      EXPECT_LE(p[0].get<double>(), 10.5);
      EXPECT_GE(p[1].get<double>(), 44.5);
      EXPECT_LE(p[1].get<double>(), 53.5);
    }
}

TEST_F(FlowRouteTest, ErrorsNameTheParameter) {
  expect_bad(get(kPath, {{"level", "3"}}), 400, "invalid_argument", "level", "level must be in [0, 2]");
  expect_bad(get(kPath, {{"format", "svg"}}), 400, "invalid_argument", "format",
             "format must be png or json");
  expect_bad(get(kPath, {{"grid", "4"}}), 400, "invalid_argument", "grid",
             "grid must be 8..1024 cells (limits::kMaxFlowGridCells)");
  expect_bad(get(kPath, {{"integrator", "euler"}}), 400, "invalid_argument", "integrator",
             "integrator must be rk2 or rk4");
  expect_bad(get(kPath, {{"d_sep", "abc"}}), 400, "invalid_argument", "d_sep",
             "d_sep must be a number, got 'abc'");
  expect_bad(get(kPath, {{"colour", "red"}}), 400, "invalid_argument", "colour",
             "unknown query parameter 'colour'");
  expect_bad(get(kPath, {{"background", "pink"}}), 400, "invalid_argument", "background",
             "background must be black or transparent");
  expect_bad(get(kPath, {{"callsign", "NOPE"}}), 422, "unprocessable", "query",
             "no flight matches the query");
  expect_bad(get("/api/v1/datasets/none/flow"), 404, "not_found", "dataset", "dataset 'none' does not exist");
  // Cost refused up front: the streamline bound of a fine grid with dense lines, and the image size.
  const Response dense =
      get(kPath, {{"grid", "1024"}, {"d_sep", "0.5"}, {"step", "0.05"}, {"sectors", "16"}});
  expect_error(dense, 413, "payload_too_large", "d_sep");
  const Response big = get(kPath, {{"grid", "1024"}, {"cell_px", "16"}, {"d_sep", "32"}, {"step", "4"}});
  expect_error(big, 413, "payload_too_large", "cell_px");
  EXPECT_NE(body(big).at("detail").get<std::string>().find("limits::kMaxFlowImagePx"), std::string::npos);
  // No garbage value makes a 5xx.
  expect_no_server_errors({kPath},
                          {"level", "grid", "sectors", "d_sep", "step", "cell_px", "format", "bundle.h"},
                          garbage_values({"2", "1.5", "8"}), 4, 3, 7);
}

std::string field_json(int w, int h) {
  nlohmann::json u = nlohmann::json::array(), v = nlohmann::json::array();
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) u.push_back(1.0 + 0.02 * j), v.push_back(0.3 * std::sin(i * 0.2));
  return nlohmann::json{
      {"format", "trailscope-flow-field"}, {"version", 1}, {"width", w}, {"height", h}, {"u", u}, {"v", v}}
      .dump();
}

TEST_F(FlowRouteTest, UploadedFieldGoesThroughTheSamePath) {
  const std::string text = field_json(48, 32);
  const Response r = send("POST", "/api/v1/flow", text, {{"level", "1"}, {"min_traffic", "0.1"}});
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(r.content_type, "image/png");
  flow::FlowParams p;
  p.lines.min_traffic = 0.1;
  flow::FlowRenderParams rp;
  rp.level = 1;
  const flow::FlowImage direct = flow::flow_image(flow::parse_field(text), p, rp, default_backend());
  EXPECT_EQ(r.bytes(), density::encode_png(direct.image));
  const Response j = send("POST", "/api/v1/flow", text, {{"format", "json"}, {"min_traffic", "0.1"}});
  ASSERT_EQ(j.status, 200) << j.body;
  EXPECT_FALSE(body(j).at("grid").at("geographic").get<bool>());
  EXPECT_GT(body(j).at("lines").size(), 5u);
  const Response not_json = send("POST", "/api/v1/flow", "{", {});
  expect_error(not_json, 415, "unsupported_format", "field");
  EXPECT_EQ(body(not_json).at("detail").get<std::string>().rfind("not JSON: ", 0), 0u) << not_json.body;
  expect_bad(send("POST", "/api/v1/flow", "[1, 2]", {}), 415, "unsupported_format", "field",
             "a vector field is a JSON object (proto/flow_field.md)");
  expect_bad(
      send("POST", "/api/v1/flow", R"({"format": "trailscope-flow-field", "version": 1, "width": 1})", {}),
      400, "invalid_argument", "width", "width must be 2..1024 cells (limits::kMaxFlowGridCells)");
  expect_bad(send("POST", "/api/v1/flow", text, {{"bbox", "0,0,1,1"}}), 400, "invalid_argument", "bbox",
             "unknown query parameter 'bbox'");
  // The body limit is the route's own.
  EXPECT_EQ(router.body_rule("POST", "/api/v1/flow").limit, limits::kMaxFlowFieldBytes);
}

// ---- tiles ------------------------------------------------------------------------------------------
constexpr int kZ = 6, kTx = 32, kTy = 22;  // lon 0..5.6°, lat 45.1..48.9°: the three flows cross it
std::string tile_path(int z = kZ, int x = kTx, int y = kTy) {
  return "/api/v1/datasets/fl/flow/" + std::to_string(z) + "/" + std::to_string(x) + "/" + std::to_string(y) +
         ".png";
}

TEST_F(FlowRouteTest, TileDrawsTheMapsLinesWhereTheJsonPutsThem) {
  const std::map<std::string, std::string> q = {{"grid", "64"}, {"level", "2"}};
  const Response r = get(tile_path(), q);
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(r.content_type, "image/png");
  const density::Image img = density::decode_png(r.bytes());
  ASSERT_EQ(img.width, 256);
  // The same map and tile through the compute library.
  flow::FlowRenderParams rp;
  rp.level = 2;
  const flow::FlowMap m = flow::flow_map(*trails, Query{}, small(), default_backend());
  EXPECT_EQ(img.rgba, flow::render_flow_tile(m, geo::TileId{kZ, kTx, kTy}, 256, rp).rgba);
  // Independently: the route's JSON lines (longitude/latitude, 6 digits) projected into the tile by the
  // Web Mercator formulas. A drawn pixel lies within the widest line's reach (half width 1.5 px + 0.5 px
  // of antialiasing) of a line; the middle of every segment inside the tile is drawn.
  const Response js = get(kPath, {{"grid", "64"}, {"level", "2"}, {"format", "json"}});
  ASSERT_EQ(js.status, 200) << js.body;
  std::vector<std::vector<std::pair<double, double>>> lines;
  const double scale = 256.0 * (1 << kZ);
  const nlohmann::json lines_json = body(js).at("lines");
  ASSERT_GT(lines_json.size(), 4u);
  for (const auto& l : lines_json) {
    auto& pts = lines.emplace_back();
    for (const auto& p : l.at("points"))
      pts.emplace_back(geo::lon_to_unit_x(p[0].get<double>()) * scale - 256.0 * kTx,
                       geo::lat_to_unit_y(p[1].get<double>()) * scale - 256.0 * kTy);
  }
  const auto dist = [&](double x, double y) {
    double best = 1e300;
    for (const auto& pts : lines)
      for (std::size_t k = 0; k + 1 < pts.size(); ++k) {
        const auto [ax, ay] = pts[k];
        const double dx = pts[k + 1].first - ax, dy = pts[k + 1].second - ay, len2 = dx * dx + dy * dy;
        const double t = len2 > 0 ? std::clamp(((x - ax) * dx + (y - ay) * dy) / len2, 0.0, 1.0) : 0;
        best = std::min(best, std::hypot(ax + t * dx - x, ay + t * dy - y));
      }
    return best;
  };
  std::size_t drawn = 0;
  for (int y = 0; y < 256; ++y)
    for (int x = 0; x < 256; ++x)
      if (img.pixel(x, y)[3] > 0) {
        ++drawn;
        ASSERT_LT(dist(x + 0.5, y + 0.5), 2.0 + 0.05) << "pixel " << x << "," << y;
      }
  EXPECT_GT(drawn, 500u);
  std::size_t inside = 0;
  for (const auto& pts : lines)
    for (std::size_t k = 0; k + 1 < pts.size(); ++k) {
      const double x = (pts[k].first + pts[k + 1].first) / 2, y = (pts[k].second + pts[k + 1].second) / 2;
      if (x < 2 || y < 2 || x > 254 || y > 254) continue;
      ++inside;
      EXPECT_GT(img.pixel(int(x), int(y))[3], 0) << "segment middle " << x << "," << y;
    }
  EXPECT_GT(inside, 20u);
  // A tile away from the traffic is transparent; level 0 draws nothing (the density tiles are that level).
  const density::Image far = density::decode_png(get(tile_path(kZ, 10, 10), q).bytes());
  EXPECT_TRUE(std::all_of(far.rgba.begin(), far.rgba.end(), [](std::uint8_t b) { return b == 0; }));
  const density::Image l0 = density::decode_png(get(tile_path(), {{"grid", "64"}, {"level", "0"}}).bytes());
  EXPECT_TRUE(std::all_of(l0.rgba.begin(), l0.rgba.end(), [](std::uint8_t b) { return b == 0; }));
}

TEST_F(FlowRouteTest, TilesShareOneMapPerWindowAndParameters) {
  // A map view's tiles at once, at two levels and two sizes: one computation.
  std::vector<std::thread> threads;
  std::vector<int> status(8);
  for (int i = 0; i < 8; ++i)
    threads.emplace_back([&, i] {
      status[i] = get(tile_path(kZ, kTx + i % 2, kTy + i / 2 % 2),
                      {{"grid", "64"}, {"level", i < 4 ? "2" : "1.25"}, {"size", i % 4 == 3 ? "512" : "256"}})
                      .status;
    });
  for (auto& t : threads) t.join();
  for (int i = 0; i < 8; ++i) EXPECT_EQ(status[i], 200) << i;
  EXPECT_EQ(app->flow_maps.computed(), 1u);
  EXPECT_EQ(app->flow_maps.entries(), 1u);
  EXPECT_GT(app->flow_maps.bytes(), 0u);
  // The ETag, and a 304 without drawing.
  const Response r = get(tile_path(), {{"grid", "64"}});
  const std::string etag = header(r, "ETag");
  ASSERT_FALSE(etag.empty());
  EXPECT_EQ(get(tile_path(), {{"grid", "64"}}, {{"if-none-match", etag}}).status, 304);
  // Another window or another field parameter is another map; another level or line width is not.
  EXPECT_EQ(get(tile_path(), {{"grid", "64"}, {"line_width", "3"}}).status, 200);
  EXPECT_EQ(app->flow_maps.computed(), 1u);
  EXPECT_EQ(get(tile_path(), {{"grid", "48"}}).status, 200);
  EXPECT_EQ(get(tile_path(), {{"grid", "64"}, {"bbox", "-2,44,12,54"}}).status, 200);
  EXPECT_EQ(app->flow_maps.computed(), 3u);
  // Deleting the dataset drops its maps.
  EXPECT_EQ(send("DELETE", "/api/v1/datasets/fl").status, 204);
  EXPECT_EQ(app->flow_maps.entries(), 0u);
}

TEST_F(FlowRouteTest, TileErrorsNameTheParameter) {
  expect_bad(get(tile_path(), {{"level", "3"}}), 400, "invalid_argument", "level", "level must be in [0, 2]");
  expect_bad(get(tile_path(), {{"cell_px", "4"}}), 400, "invalid_argument", "cell_px",
             "unknown query parameter 'cell_px'");
  expect_bad(get(tile_path(), {{"format", "json"}}), 400, "invalid_argument", "format",
             "unknown query parameter 'format'");
  expect_bad(get(tile_path(), {{"size", "300"}}), 400, "invalid_argument", "size", "size must be 256 or 512");
  expect_error(get(tile_path(23, 0, 0)), 400, "invalid_argument", "z");
  expect_error(get(tile_path(3, 8, 0)), 400, "invalid_argument", "x");
  expect_bad(get(tile_path(), {{"grid", "4"}}), 400, "invalid_argument", "grid",
             "grid must be 8..1024 cells (limits::kMaxFlowGridCells)");
  expect_bad(get(tile_path(), {{"callsign", "NOPE"}}), 422, "unprocessable", "query",
             "no flight matches the query");
  expect_bad(get("/api/v1/datasets/none/flow/1/0/0.png"), 404, "not_found", "dataset",
             "dataset 'none' does not exist");
  expect_error(get(tile_path(), {{"grid", "1024"}, {"d_sep", "0.5"}, {"step", "0.05"}, {"sectors", "16"}}),
               413, "payload_too_large", "d_sep");
  EXPECT_EQ(app->flow_maps.entries(), 0u) << "nothing cached for refused requests";
  expect_no_server_errors({tile_path()}, {"level", "grid", "line_width", "size", "d_sep", "bundle.h"},
                          garbage_values({"2", "1.5", "256"}), 4, 3, 7);
}

}  // namespace
}  // namespace trailscope::server
