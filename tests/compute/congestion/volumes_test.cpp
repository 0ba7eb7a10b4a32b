// Sector uploads (every refusal with its exact message) and the 20 NM grid (cell ids, bounds, and that
// the cells partition space), checked against the definitions in congestion/volumes.hpp.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "trailscope/congestion/volumes.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"

namespace trailscope::congestion {
namespace {

nlohmann::json feature(const nlohmann::json& ring, const nlohmann::json& props) {
  return {{"type", "Feature"},
          {"properties", props},
          {"geometry", {{"type", "Polygon"}, {"coordinates", nlohmann::json::array({ring})}}}};
}
nlohmann::json square_ring() {
  return {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}};
}
nlohmann::json props(const std::string& name = "S1") {
  return {{"name", name}, {"lower_fl", 100}, {"upper_fl", 200}};
}
nlohmann::json collection(std::vector<nlohmann::json> features) {
  return {{"type", "FeatureCollection"}, {"features", features}};
}

void expect_refused(const nlohmann::json& doc, const std::string& message,
                    Error::Kind kind = Error::Kind::unprocessable) {
  try {
    parse_sectors(doc);
    ADD_FAILURE() << "accepted: " << doc.dump();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), kind);
    EXPECT_EQ(e.param(), "sectors");
    EXPECT_EQ(std::string(e.what()), message);
  }
}

TEST(Sectors, ParsesAndRoundTrips) {
  auto p = props("EDUU");
  p["peak"] = 40;
  p["sustained"] = nullptr;  // null counts as absent
  const auto doc = collection({feature(square_ring(), p), feature({{2, 2}, {3, 2}, {3, 3}}, props("B"))});
  const auto s = parse_sectors(doc);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0].name, "EDUU");
  EXPECT_EQ(s[0].ring.size(), 4u);  // the closing vertex is dropped
  EXPECT_EQ(s[0].lower_m, 100 * 100 * 0.3048);
  EXPECT_EQ(s[0].upper_m, 200 * 100 * 0.3048);
  EXPECT_EQ(s[0].peak, 40);
  EXPECT_FALSE(s[0].sustained);
  EXPECT_EQ(s[1].ring.size(), 3u);  // an unclosed ring is accepted
  const auto again = parse_sectors(sectors_to_geojson(s));
  ASSERT_EQ(again.size(), 2u);
  EXPECT_EQ(again[0].ring, s[0].ring);
  EXPECT_EQ(again[0].peak, s[0].peak);
  EXPECT_EQ(again[1].name, "B");
}

TEST(Sectors, RefusalsNameTheFeature) {
  expect_refused(nlohmann::json::array(), "sectors must be a GeoJSON FeatureCollection");
  expect_refused(collection({}), "sectors: the FeatureCollection has no features");
  expect_refused(collection({feature(square_ring(), props()), {{"type", "Point"}}}),
                 "feature 1: not a GeoJSON Feature");
  auto no_name = props();
  no_name.erase("name");
  expect_refused(collection({feature(square_ring(), no_name)}), "feature 0: property 'name' is missing");
  expect_refused(collection({feature(square_ring(), props()), feature(square_ring(), props())}),
                 "feature 1 (\"S1\"): the name is already used");
  auto bad_fl = props();
  bad_fl["lower_fl"] = 250;
  expect_refused(collection({feature(square_ring(), bad_fl)}),
                 "feature 0 (\"S1\"): lower_fl must be below upper_fl");
  auto str_fl = props();
  str_fl["upper_fl"] = "200";
  expect_refused(collection({feature(square_ring(), str_fl)}),
                 "feature 0 (\"S1\"): property 'upper_fl' must be a number");
  auto neg_peak = props();
  neg_peak["peak"] = -3;
  expect_refused(collection({feature(square_ring(), neg_peak)}),
                 "feature 0 (\"S1\"): property 'peak' must be >= 0");
  auto holes = feature(square_ring(), props());
  holes["geometry"]["coordinates"].push_back({{0.2, 0.2}, {0.4, 0.2}, {0.4, 0.4}, {0.2, 0.2}});
  expect_refused(collection({holes}),
                 "feature 0 (\"S1\"): the Polygon has holes; a sector is one ring (split it into sectors)");
  auto multi = feature(square_ring(), props());
  multi["geometry"]["type"] = "MultiPolygon";
  expect_refused(
      collection({multi}),
      "feature 0 (\"S1\"): the geometry must be a Polygon, not a MultiPolygon (upload one feature per "
      "part)");
  expect_refused(collection({feature({{0, 0}, {2, 2}, {2, 0}, {0, 3}, {0, 0}}, props())}),
                 "feature 0 (\"S1\"): edges 0 and 2 intersect (the ring must be a simple polygon)");
  expect_refused(
      collection({feature({{170, 0}, {-170, 0}, {-170, 1}, {170, 1}}, props())}),
      "feature 0 (\"S1\"): edge 0 crosses 180° of longitude; split the sector at the antimeridian");
  expect_refused(collection({feature({{0, 0}, {1, 0}, {2, 0}}, props())}),
                 "feature 0 (\"S1\"): the ring has zero area");
  expect_refused(collection({feature({{0, 0}, {1, 0}, {1, 0}, {0, 1}}, props())}),
                 "feature 0 (\"S1\"): positions 1 and 2 are equal");
  expect_refused(collection({feature({{0, 0}, {1, 0}, {0, 0}}, props())}),
                 "feature 0 (\"S1\"): the ring needs at least 3 distinct vertices");
  expect_refused(collection({feature({{0, 0}, {181, 0}, {0, 1}}, props())}),
                 "feature 0 (\"S1\"): position 1 is outside lon [-180, 180], lat [-90, 90]");
  expect_refused(collection({feature({{0, 0}, {1, 0}, {1, 1, 5, 6}}, props())}),
                 "feature 0 (\"S1\"): position 2 is not [lon, lat]");
  std::vector<nlohmann::json> many(limits::kMaxSectors + 1, feature(square_ring(), props()));
  expect_refused(collection(many), "sectors: 1001 features, more than the limit of 1000",
                 Error::Kind::payload_too_large);
  nlohmann::json ring = nlohmann::json::array();
  for (std::size_t i = 0; i <= limits::kMaxSectorVertices; ++i) {
    const double a = 2 * M_PI * static_cast<double>(i) / (limits::kMaxSectorVertices + 1);
    ring.push_back({std::cos(a), std::sin(a)});
  }
  ring.push_back(ring[0]);
  expect_refused(collection({feature(ring, props())}),
                 "feature 0: 10002 positions in the ring, more than the limit of 10000 vertices",
                 Error::Kind::payload_too_large);
}

TEST(Sectors, PolygonContainsIsClosed) {
  const auto s = parse_sectors(collection({feature(square_ring(), props())}))[0];
  EXPECT_TRUE(polygon_contains(s, 0.5, 0.5));
  EXPECT_TRUE(polygon_contains(s, 0, 0));    // a vertex
  EXPECT_TRUE(polygon_contains(s, 1, 0.5));  // an edge
  EXPECT_FALSE(polygon_contains(s, 1.0000001, 0.5));
  EXPECT_FALSE(polygon_contains(s, -0.5, 0.5));
}

TEST(Grid, CellIdsAndBounds) {
  const GridCell c = grid_cell_at(45.1, 10.0, 10200);  // FL334: layer 11
  EXPECT_EQ(c.row, 405);
  EXPECT_EQ(c.layer, 11);
  const double w = (1.0 / 3.0) / std::cos((45.0 + 1.0 / 6.0) * M_PI / 180.0);
  EXPECT_NEAR(grid_column_width(405), w, 1e-15);
  EXPECT_EQ(c.col, static_cast<int>(std::floor(190.0 / w)));
  EXPECT_EQ(grid_cell_id(c), "r405c" + std::to_string(c.col) + "l11");
  EXPECT_EQ(parse_grid_cell_id(grid_cell_id(c)), c);
  EXPECT_EQ(parse_grid_cell_id("r0c0l-2"), (GridCell{0, 0, -2}));
  for (const char* bad : {"r405c10", "x1c1l1", "r540c0l0", "r01c0l0", "r1c0l-0", "r1c0l0x", "r1c99999l0"})
    EXPECT_THROW(parse_grid_cell_id(bad), Error) << bad;
  const CellBounds b = grid_cell_bounds(c);
  EXPECT_EQ(b.south, -90.0 + 405 / 3.0);
  EXPECT_DOUBLE_EQ(b.lower_m, 11 * 3000 * 0.3048);
  // 20 NM wide at the row's middle latitude: w·60·cos(φm) NM.
  EXPECT_NEAR((b.east - b.west) * 60 * std::cos((b.south + b.north) / 2 * M_PI / 180), 20.0, 1e-9);
  EXPECT_NEAR((b.north - b.south) * 60, 20.0, 1e-9);
  // Edges: lat 90 is in the top row, lon 180 is lon -180.
  EXPECT_EQ(grid_cell_at(90, 0, 0).row, kGridRows - 1);
  EXPECT_EQ(grid_cell_at(10, 180, 0), grid_cell_at(10, -180, 0));
  EXPECT_EQ(grid_cell_at(0, 0, -1).layer, -1);
}

// Random points fall in the cell whose bounds hold them (south/west/lower inside, north/east/upper not),
// and points on a boundary go to the north / east / upper side.
TEST(Grid, CellsPartitionSpace) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> lat(-90, 90), lon(-180, 180), alt(-500, 20000);
  for (int i = 0; i < 200000; ++i) {
    const double la = lat(rng), lo = lon(rng), al = alt(rng);
    const GridCell c = grid_cell_at(la, lo, al);
    const CellBounds b = grid_cell_bounds(c);
    ASSERT_TRUE(la >= b.south && la < b.north) << la;
    ASSERT_TRUE(lo >= b.west && lo < b.east) << lo;
    ASSERT_TRUE(al >= b.lower_m && al < b.upper_m) << al;
  }
  const GridCell c{300, 500, 3};
  const CellBounds b = grid_cell_bounds(c);
  EXPECT_EQ(grid_cell_at(b.south, b.west, b.lower_m), c);
  EXPECT_EQ(grid_cell_at(b.north, b.west, b.lower_m).row, 301);
  EXPECT_EQ(grid_cell_at(b.south, b.east, b.lower_m).col, 501);
  EXPECT_EQ(grid_cell_at(b.south, b.west, b.upper_m).layer, 4);
}

TEST(Grid, Extent) {
  const GridExtent e = make_grid_extent(BBox{-10, 40, 10, 50}, 0, 60000 * 0.3048);
  EXPECT_EQ(e.row_min, 390);
  EXPECT_EQ(e.row_max, 420);
  EXPECT_EQ(e.layer_min, 0);
  EXPECT_EQ(e.layer_max, 20);
  std::uint64_t n = 0;
  for (int r = e.row_min; r <= e.row_max; ++r) {
    const double w = grid_column_width(r);
    n += static_cast<std::uint64_t>(std::floor(190 / w) - std::floor(170 / w) + 1);
  }
  EXPECT_EQ(e.cell_count(), n * 21);
  EXPECT_TRUE(e.contains(grid_cell_at(45, 0, 1000)));
  EXPECT_FALSE(e.contains(grid_cell_at(45, 20, 1000)));
  EXPECT_FALSE(e.contains(grid_cell_at(45, 0, 20000)));
  // Across 180°: the columns from 170 to 180 and from -180 to -170.
  const GridExtent d = make_grid_extent(BBox{170, 0, -170, 1}, 0, 100);
  EXPECT_TRUE(d.contains(grid_cell_at(0.5, 175, 50)));
  EXPECT_TRUE(d.contains(grid_cell_at(0.5, -175, 50)));
  EXPECT_FALSE(d.contains(grid_cell_at(0.5, 0, 50)));
  try {
    make_grid_extent(BBox{}, -1e5, 1e5);
    ADD_FAILURE();
  } catch (const Error& err) {
    EXPECT_EQ(err.kind(), Error::Kind::payload_too_large);
    EXPECT_EQ(err.param(), "bbox");
  }
}

}  // namespace
}  // namespace trailscope::congestion
