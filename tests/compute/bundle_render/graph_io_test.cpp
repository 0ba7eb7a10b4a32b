// Graph input (graph_io.hpp): every file of shared/data/bundling against the counts verified in its
// SOURCES.md, the vega-datasets airline CSVs against counts computed here with a separate reader, known
// coordinates, exact error messages, and the .trl round trip.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>

#include "test_support.hpp"
#include "trailscope/bundling/graph_io.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"

namespace trailscope::bundling {
namespace {

std::filesystem::path bundling_data(const std::string& rel) {
  return test::shared_data("bundling/" + rel);
}

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

#define REQUIRE_FILE(p) \
  if (!std::filesystem::exists(p)) GTEST_SKIP() << (p) << " absent"

/// Every polyline of `g` has exactly `points` points.
void expect_points_each(const Graph& g, std::size_t points) {
  for (std::size_t i = 0; i < g.edges.size(); ++i) ASSERT_EQ(g.edges.end(i) - g.edges.begin(i), points) << i;
}

struct Expected {
  const char* file;
  GraphFormat format;
  std::size_t edges, nodes, points_each, skipped;
};

// Counts from the data set's manifest, $TRAILSCOPE_SHARED/data/bundling/SOURCES.md ("verified counts").
const Expected kFiles[] = {
    {"classic/airlines.xml", GraphFormat::graphml, 2101, 235, 2, 0},
    {"classic/migrations.xml", GraphFormat::graphml, 9780, 1715, 2, 0},
    {"epb/airlines.json", GraphFormat::node_link, 2101, 235, 2, 0},
    {"epb/migrations.json", GraphFormat::node_link, 6487, 1702, 2, 0},
    {"epb/airtraffic.json", GraphFormat::node_link, 16494, 1533, 2, 0},
    {"cubu/3.US-1", GraphFormat::trl, 2099, 0, 50, 0},
    {"cubu/3.US-1_iter9", GraphFormat::trl, 2099, 0, 50, 2},  // "maxv:"/"minv:" header fields
    {"cubu/5.Poker", GraphFormat::trl, 2127, 0, 50, 0},
    {"cubu/ds1", GraphFormat::trl, 81, 0, 50, 0},
    {"cubu/ds2", GraphFormat::trl, 554, 0, 50, 0},
    {"cubu/ds3", GraphFormat::trl, 2100, 0, 50, 0},
    {"cubu/ds5", GraphFormat::trl, 2396, 0, 50, 0},
    {"cubu/s1", GraphFormat::trl, 48, 0, 50, 0},
    {"cubu/s3", GraphFormat::trl, 106, 0, 50, 0},
    {"cubu/s6", GraphFormat::trl, 24, 0, 50, 0},
    {"cubu/teat0.xy", GraphFormat::trl, 1, 0, 804, 0},
    {"cubu/teat3.xy", GraphFormat::trl, 1, 0, 804, 0},
    {"cubu/us_counties_lamp.trl", GraphFormat::trl, 5333, 0, 2, 0},
    {"cubu/us_counties_lsp.trl", GraphFormat::trl, 30172, 0, 2, 0},
    {"cubu/segmentation_lamp.trl", GraphFormat::trl, 1537, 0, 2, 0},
};

TEST(GraphIo, EveryBundlingFileHasItsVerifiedCounts) {
  for (const Expected& e : kFiles) {
    SCOPED_TRACE(e.file);
    const auto path = bundling_data(e.file);
    REQUIRE_FILE(path);
    const std::string bytes = slurp(path);
    EXPECT_EQ(detect_graph_format(bytes), e.format);
    const Graph g = read_graph(path);
    EXPECT_EQ(g.format, e.format);
    EXPECT_EQ(g.edges.size(), e.edges);
    EXPECT_EQ(g.nodes, e.nodes);
    EXPECT_EQ(g.skipped, e.skipped);
    EXPECT_EQ(g.weight.size(), g.edges.size());
    EXPECT_FALSE(g.geographic);
    expect_points_each(g, e.points_each);
  }
}

TEST(GraphIo, UsCountiesLspHas2131DistinctEndpoints) {
  const auto path = bundling_data("cubu/us_counties_lsp.trl");
  REQUIRE_FILE(path);
  const Graph g = read_graph(path);
  std::set<std::pair<double, double>> ends;
  for (std::size_t i = 0; i < g.edges.size(); ++i)
    for (std::size_t k : {g.edges.begin(i), g.edges.end(i) - 1}) ends.emplace(g.edges.x[k], g.edges.y[k]);
  EXPECT_EQ(ends.size(), 2131u);  // SOURCES.md
}

TEST(GraphIo, AirlinesGraphmlCoordinatesAreTenTimesLonLat) {
  const auto path = bundling_data("classic/airlines.xml");
  REQUIRE_FILE(path);
  const Graph g = read_graph(path);
  // The first edge is 0 → 136; node 0 is LIT(lngx=-92.224444,laty=34.729444): x = 10·lon, y = −10·lat.
  EXPECT_NEAR(g.edges.x[0], 10 * -92.224444, 1e-9);
  EXPECT_NEAR(g.edges.y[0], -10 * 34.729444, 1e-9);
  for (double w : g.weight) EXPECT_EQ(w, 1.0);
  // The JSON copy of the same graph has y = +10·lat.
  const auto json = bundling_data("epb/airlines.json");
  REQUIRE_FILE(json);
  const Graph j = read_graph(json);
  EXPECT_EQ(j.edges.x[0], g.edges.x[0]);
  EXPECT_NEAR(j.edges.y[0], -g.edges.y[0], 1e-9);
}

TEST(GraphIo, MigrationsEdgeWeightsAreTheValueKey) {
  const auto path = bundling_data("classic/migrations.xml");
  REQUIRE_FILE(path);
  // Independent sum: every <data key="value">N</data> of the file (only edges carry that key).
  const std::string text = slurp(path);
  double expected = 0;
  const std::string tag = "<data key=\"value\">";
  for (std::size_t at = text.find(tag); at != std::string::npos; at = text.find(tag, at + 1))
    expected += std::stod(text.substr(at + tag.size(), 20));
  const Graph g = read_graph(path);
  double sum = 0;
  for (double w : g.weight) sum += w;
  EXPECT_EQ(g.weight[0], 580.0);
  EXPECT_EQ(sum, expected);
}

/// A plain CSV reader (no quote handling), sharing nothing with graph_io.
std::vector<std::vector<std::string>> csv_rows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::stringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::vector<std::string> f(1);
    for (char c : line) c == ',' ? f.emplace_back() : (f.back() += c, f.back());
    rows.push_back(f);
  }
  return rows;
}

TEST(GraphIo, VegaAirportFlightsByNameAreProjectedToWebMercator) {
  const auto dir = test::source_dir() / "web/node_modules/vega-datasets/data";
  REQUIRE_FILE(dir / "flights-airport.csv");
  const auto flights = csv_rows(slurp(dir / "flights-airport.csv"));
  const auto airports = csv_rows(slurp(dir / "airports.csv"));
  ASSERT_EQ(flights[0], (std::vector<std::string>{"origin", "destination", "count"}));
  ASSERT_EQ(airports[0][0], "iata");
  std::map<std::string, std::pair<double, double>> lonlat;  // iata → (lon, lat)
  // A few names hold quoted commas; latitude and longitude are always the last two fields.
  for (std::size_t r = 1; r < airports.size(); ++r) {
    const auto& a = airports[r];
    lonlat[a[0]] = {std::stod(a[a.size() - 1]), std::stod(a[a.size() - 2])};
  }
  std::size_t edges = 0, skipped = 0;
  double count = 0;
  std::set<std::string> used;
  for (std::size_t r = 1; r < flights.size(); ++r) {
    const auto& f = flights[r];
    if (!lonlat.count(f[0]) || !lonlat.count(f[1]) || lonlat[f[0]] == lonlat[f[1]]) {
      ++skipped;
      continue;
    }
    ++edges, count += std::stod(f[2]), used.insert(f[0]), used.insert(f[1]);
  }
  ASSERT_EQ(edges, 5366u);

  const Graph g = read_graph(dir / "flights-airport.csv", dir / "airports.csv");
  EXPECT_EQ(g.format, GraphFormat::od_csv);
  EXPECT_EQ(g.edges.size(), edges);
  EXPECT_EQ(g.skipped, skipped);
  EXPECT_EQ(g.nodes, used.size());
  EXPECT_TRUE(g.geographic);
  EXPECT_TRUE(g.y_up);
  double sum = 0;
  for (double w : g.weight) sum += w;
  EXPECT_EQ(sum, count);
  // Row 1 is ABE → ATL: EPSG:3857 x = R·λ, y = R·ln tan(π/4 + φ/2).
  const double R = 6378137.0, d = M_PI / 180;
  const auto [lon, lat] = lonlat["ATL"];
  EXPECT_NEAR(g.edges.x[1], R * lon * d, 1e-6);
  EXPECT_NEAR(g.edges.y[1], R * std::log(std::tan(M_PI / 4 + lat * d / 2)), 1e-6);
}

TEST(GraphIo, SelfContainedCsvInDegreesAndPlaneUnits) {
  const std::string deg =
      "origin_lon,origin_lat,dest_lon,dest_lat,count\r\n0,0,90,0,3\r\n10,20,10,20,1\r\n\r\n-180,45,180,-45,"
      "2\r\n";
  const Graph g = parse_graph(deg);
  EXPECT_EQ(g.format, GraphFormat::od_csv);
  EXPECT_TRUE(g.geographic);
  ASSERT_EQ(g.edges.size(), 2u);
  EXPECT_EQ(g.skipped, 1u);  // the zero-length edge
  EXPECT_EQ(g.nodes, 4u);
  EXPECT_NEAR(g.edges.x[1], 6378137.0 * M_PI / 2, 1e-6);
  EXPECT_EQ(g.weight, (std::vector<double>{3, 2}));

  const Graph p = parse_graph("x1,y1,x2,y2\n1,2,3,4\n\"5\",6,7,8\n");
  EXPECT_FALSE(p.geographic);
  EXPECT_FALSE(p.y_up);
  EXPECT_EQ(p.edges.x, (std::vector<double>{1, 3, 5, 7}));
  EXPECT_EQ(p.edges.y, (std::vector<double>{2, 4, 6, 8}));
}

TEST(GraphIo, GraphmlKeysAreResolvedByAttrName) {
  // yEd/networkx style ids (d0, d1, …): the names come from <key attr.name>; "weight" is an edge key.
  const std::string doc = R"(<?xml version="1.0"?>
<graphml xmlns="http://graphml.graphdrawing.org/xmlns">
  <key id="d0" for="node" attr.name="y" attr.type="double"/>
  <key id="d1" for="node" attr.name="x" attr.type="double"/>
  <key id="d2" for="edge" attr.name="weight" attr.type="double"/>
  <graph edgedefault="directed">
    <node id="n0"><data key="d1">1.5</data><data key="d0">-2</data></node>
    <node id="n1"><data key="d1">3</data><data key="d0">4</data></node>
    <node id="n2"><data key="d1">1.5</data><data key="d0">-2</data></node>
    <edge source="n0" target="n1"><data key="d2">7.25</data></edge>
    <edge source="n1" target="n0"/>
    <edge source="n0" target="n2"/>
    <edge source="n0" target="n9"/>
  </graph>
</graphml>)";
  EXPECT_EQ(detect_graph_format(doc), GraphFormat::graphml);
  const Graph g = parse_graph(doc);
  ASSERT_EQ(g.edges.size(), 2u);
  EXPECT_EQ(g.skipped, 2u);  // n0 → n2 joins two records of one position, n9 is unknown
  EXPECT_EQ(g.edges.x, (std::vector<double>{1.5, 3, 3, 1.5}));
  EXPECT_EQ(g.edges.y, (std::vector<double>{-2, 4, 4, -2}));
  EXPECT_EQ(g.weight, (std::vector<double>{7.25, 1}));
  EXPECT_EQ(g.nodes, 2u);
  EXPECT_FALSE(g.geographic);
}

TEST(GraphIo, NodeLinkAcceptsIndicesAndEdges) {
  const std::string doc =
      R"({"nodes":[{"id":"a","x":0,"y":0},{"id":"b","x":1,"y":2},{"id":"c","x":"3","y":4}],)"
      R"("edges":[{"source":"a","target":"b","weight":2},{"source":2,"target":0},{"source":"a","target":"z"},)"
      R"({"source":"b","target":"b"}]})";
  const Graph g = parse_graph(doc);
  ASSERT_EQ(g.edges.size(), 2u);
  EXPECT_EQ(g.skipped, 2u);  // unknown node z, self-loop b → b
  EXPECT_EQ(g.edges.x, (std::vector<double>{0, 1, 3, 0}));
  EXPECT_EQ(g.weight, (std::vector<double>{2, 1}));
  EXPECT_EQ(g.nodes, 3u);
}

/// The Error thrown by `f`, or a failure.
template <class F>
Error error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "no error thrown";
  return Error(Error::Kind::internal, "", "");
}

void expect_error(const Error& e, Error::Kind kind, const std::string& param, const std::string& message) {
  EXPECT_EQ(e.kind(), kind) << e.what();
  EXPECT_EQ(e.param(), param);
  EXPECT_EQ(std::string(e.what()), message);
}

TEST(GraphIo, MalformedInputsGiveExactMessages) {
  using K = Error::Kind;
  const GraphFormat trl = GraphFormat::trl, csv = GraphFormat::od_csv;
  expect_error(error_of([] { parse_graph("0: 1 2 3 4\r\n1: 1 2 x 4\r\n"); }), K::unprocessable, "input",
               "trl line 2: 'x' is not a finite number");
  expect_error(error_of([] { parse_graph("0: 1 2 3 4\n\n1: 1 2\n 3\n"); }), K::unprocessable, "input",
               "trl line 3: polyline '1' has an odd number of coordinates (3)");
  expect_error(error_of([&] { parse_graph("1 2 3 4\n", {}, &trl); }), K::unprocessable, "input",
               "trl line 1: coordinate '1' before the first polyline label (\"0:\")");
  expect_error(error_of([] { parse_graph("0: 1 2\n1: nan 1 2 3\n"); }), K::unprocessable, "input",
               "trl line 2: 'nan' is not a finite number");
  expect_error(error_of([] { parse_graph("0: 1 2\n1: 3 4\n"); }), K::unprocessable, "input",
               "trl: no polyline with at least 2 points (2 skipped)");
  expect_error(
      error_of([] { parse_graph("<?xml version=\"1.0\"?>\n<graphml>\n<graph>\n<node id=\"a\">\n</graph>"); }),
      K::unprocessable, "input", "graphml line 5: XML error: Start-end tags mismatch");
  expect_error(
      error_of([] {
        parse_graph(
            "<graphml><key id=\"d0\" for=\"node\" attr.name=\"x\"/><key id=\"d1\" for=\"node\" "
            "attr.name=\"y\"/><graph>\n<node id=\"a\"><data key=\"d0\">1</data><data "
            "key=\"d1\">2</data></node>\n<node id=\"b\"><data key=\"d0\">3</data></node></graph></graphml>");
      }),
      K::unprocessable, "input",
      "graphml line 3: node 'b' has no y (no <data> for a key with attr.name=\"y\")");
  expect_error(error_of([] { parse_graph(R"({"nodes":[{"id":1,"x":0,"y":0},{"id":2,"y":1}],"links":[]})"); }),
               K::unprocessable, "input", "node_link: nodes[1] has no x");
  expect_error(
      error_of([] { parse_graph("{\"nodes\": [\n{\"id\": 1,}\n]}"); }), K::unprocessable, "input",
      "node_link line 2: JSON error: [json.exception.parse_error.101] parse error at line 2, column 10: "
      "syntax error while parsing object key - unexpected '}'; expected string literal");
  expect_error(
      error_of([] { parse_graph("origin,destination,count\nA,B,1\nA,C\n", "iata,lat,lon\nA,1,2\n"); }),
      K::unprocessable, "input", "od_csv line 3: 2 fields, the header has 3");
  expect_error(error_of([] { parse_graph("origin,destination\nA,B\n"); }), K::unprocessable, "nodes",
               "od_csv: edges given by node name need a nodes table (iata, id or name; latitude, longitude)");
  expect_error(error_of([] { parse_graph("origin,destination\nA,B\n", "iata,lat,lon\nA,91,0\nB,0,0\n"); }),
               K::unprocessable, "nodes", "nodes csv line 2: latitude 91.000000 is outside [-90, 90]");
  expect_error(error_of([&] { parse_graph("a,b\n1,2\n", {}, &csv); }), K::unprocessable, "input",
               "od_csv line 1: the header has neither coordinate columns (x1,y1,x2,y2 or "
               "origin_lon,origin_lat,dest_lon,dest_lat) nor origin,destination names");
  expect_error(error_of([] { parse_graph("x1,y1,x2,y2\n1,2,3,\n"); }), K::unprocessable, "input",
               "od_csv line 2: y2 '' is not a finite number");
  for (const char* junk : {"", "hello world\n", "<html></html>", "1,2\n3,4\n"})
    expect_error(error_of([&] { parse_graph(junk); }), K::unsupported_format, "input",
                 "the input is not a graph or trail file: expected GraphML, node-link JSON, an "
                 "origin-destination CSV or CUBu trail text (.trl)");
  expect_error(error_of([] { parse_graph_format("xml"); }), K::invalid_argument, "format",
               "format 'xml' is not a graph format (graphml, node_link, od_csv, trl)");
  expect_error(error_of([] { read_graph("/nonexistent/graph.xml"); }), K::not_found, "input",
               "cannot read input file /nonexistent/graph.xml");
}

TEST(GraphIo, TooManyEdgesIsPayloadTooLarge) {
  std::string text;
  text.reserve((limits::kMaxBundleEdges + 1) * 12);
  for (std::size_t i = 0; i <= limits::kMaxBundleEdges; ++i) text += "0: 0 0 1 1\n";
  expect_error(error_of([&] { parse_graph(text); }), Error::Kind::payload_too_large, "input",
               "the input has more than 2000000 edges/trails (limits::kMaxBundleEdges)");
}

TEST(GraphIo, WriteTrlRoundTripsExactly) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1e6, 1e6);
  Polylines lines;
  for (int i = 0; i < 50; ++i) {
    std::vector<double> xs(2 + i % 7), ys(xs.size());
    for (std::size_t k = 0; k < xs.size(); ++k) xs[k] = u(rng), ys[k] = u(rng) * 1e-9;
    lines.add(xs, ys);
  }
  const Graph back = parse_graph(write_trl(lines));
  EXPECT_EQ(back.edges.x, lines.x);
  EXPECT_EQ(back.edges.y, lines.y);
  EXPECT_EQ(back.edges.offsets, lines.offsets);

  const auto path = bundling_data("cubu/3.US-1");
  REQUIRE_FILE(path);
  const Graph us = read_graph(path);
  const Graph again = parse_graph(write_trl(us.edges));
  EXPECT_EQ(again.edges.x, us.edges.x);
  EXPECT_EQ(again.edges.offsets, us.edges.offsets);
}

}  // namespace
}  // namespace trailscope::bundling
