// Exports of a window through the real router: the streamed GeoJSON and CSV of the Europe day parsed here
// and compared with the API's JSON (the flight list for which flights, GET /flights/{n}?clip=1 for their
// points), the size limit with its exact message and a count made here, the summary's CSV tables against
// its JSON, and the refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "europe_dataset.hpp"
#include "route_fixture.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::server {
namespace {

constexpr double kT0 = 1514764800.0;  // 2018-01-01T00:00:00Z

// A CSV line split on commas, with RFC 4180 quotes.
std::vector<std::string> csv_fields(const std::string& line) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"')
        out.back() += '"', ++i;
      else if (c == '"')
        quoted = false;
      else
        out.back() += c;
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      out.emplace_back();
    } else {
      out.back() += c;
    }
  }
  return out;
}
std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

class ExportEurope : public test_routes::RouteFixture {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(test_routes::europe_so6())) GTEST_SKIP() << "the Europe SO6 day is absent";
    open(test_routes::europe_dataset("eu"));
  }
  // The window: 06:00-12:00 between FL100 and FL300 over Europe (thousands of flights, tens of thousands
  // of points: an export of many pieces).
  std::map<std::string, std::string> window(std::map<std::string, std::string> extra = {}) {
    std::map<std::string, std::string> q = {{"t0", std::to_string(kT0 + 6 * 3600)},
                                            {"t1", std::to_string(kT0 + 12 * 3600)},
                                            {"alt_min", "10000"},
                                            {"alt_max", "30000"},
                                            {"bbox", "-10,35,30,60"}};
    q.insert(extra.begin(), extra.end());
    return q;
  }
  std::vector<std::uint32_t> listed_ids() {
    std::vector<std::uint32_t> ids;
    for (int page = 0;; ++page) {
      const auto j =
          body(get("/api/v1/datasets/eu/flights",
                   window({{"sort", "id"}, {"page", std::to_string(page)}, {"page_size", "1000"}})));
      if (j["flights"].empty()) break;
      for (const auto& f : j["flights"]) ids.push_back(f["id"]);
    }
    return ids;
  }
};

TEST_F(ExportEurope, GeoJsonEqualsTheFlightList) {
  const Response r = get("/api/v1/datasets/eu/export", window({{"format", "geojson"}}));
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(r.content_type, "application/geo+json");
  EXPECT_EQ(header(r, "Content-Disposition"), "attachment; filename=\"eu-flights.geojson\"");
  ASSERT_TRUE(r.stream) << "an export is streamed";
  // Drawn piece by piece as the server sends it: several pieces, each about kExportPieceBytes at most
  // (a piece ends after the flight that crosses the mark).
  std::string all, piece;
  int pieces = 0;
  for (bool more = true; more;) {
    piece.clear();
    more = r.stream(piece);
    ++pieces;
    EXPECT_LT(piece.size(), limits::kExportPieceBytes + 200'000);
    all += piece;
  }
  EXPECT_GT(pieces, 2);
  const auto fc = nlohmann::json::parse(all);
  EXPECT_EQ(fc["type"], "FeatureCollection");
  EXPECT_EQ(fc["dataset"], "eu");
  const auto ids = listed_ids();
  ASSERT_GT(ids.size(), 300u);
  ASSERT_EQ(fc["features"].size(), ids.size());
  EXPECT_EQ(fc["flights"], ids.size());
  std::uint64_t points = 0;
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const auto& feature = fc["features"][k];
    ASSERT_EQ(feature["properties"]["id"], ids[k]);
    points += feature["properties"]["times"].size();
    if (k % 25 == 0) {  // every 25th against the flight route, whole
      auto q = window({{"clip", "1"}});
      const auto one = body(get("/api/v1/datasets/eu/flights/" + std::to_string(ids[k]), q));
      EXPECT_EQ(feature, one) << ids[k];
    }
  }
  EXPECT_EQ(fc["points"], points);
}

TEST_F(ExportEurope, CsvEqualsTheFlightRoute) {
  const Response r = get("/api/v1/datasets/eu/export", window({{"format", "csv"}}));
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(r.content_type, "text/csv; charset=utf-8");
  EXPECT_EQ(header(r, "Content-Disposition"), "attachment; filename=\"eu-flights.csv\"");
  const auto rows = lines(r.collect());
  ASSERT_GT(rows.size(), 1u);
  EXPECT_EQ(rows[0], "flight_id,icao24,callsign,t,lat,lon,alt_m,speed_ms,track_deg,vrate_ms,on_ground");
  std::map<std::uint32_t, std::vector<std::vector<std::string>>> by_flight;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    auto f = csv_fields(rows[i]);
    ASSERT_EQ(f.size(), 11u) << rows[i];
    by_flight[static_cast<std::uint32_t>(std::stoul(f[0]))].push_back(std::move(f));
  }
  const auto ids = listed_ids();
  ASSERT_EQ(by_flight.size(), ids.size());
  const auto value = [](const std::string& s) { return s.empty() ? NAN : std::stod(s); };
  std::size_t checked = 0;
  for (std::size_t k = 0; k < ids.size(); k += 10) {
    const auto one =
        body(get("/api/v1/datasets/eu/flights/" + std::to_string(ids[k]), window({{"clip", "1"}})));
    const auto& csv = by_flight.at(ids[k]);
    const auto& props = one["properties"];
    ASSERT_EQ(csv.size(), props["times"].size()) << ids[k];
    for (std::size_t i = 0; i < csv.size(); ++i) {
      EXPECT_EQ(csv[i][2], props["callsign"]);
      EXPECT_EQ(std::stod(csv[i][3]), props["times"][i].get<double>());
      const auto& c = one["geometry"]["coordinates"][i];
      // Float columns: the CSV's shortest float text and the JSON's double of the same float.
      EXPECT_EQ(float(value(csv[i][5])), c[0].get<float>());
      EXPECT_EQ(float(value(csv[i][4])), c[1].get<float>());
      EXPECT_EQ(float(value(csv[i][6])), props["altitudes_m"][i].get<float>());
      if (props["speeds_ms"][i].is_null())
        EXPECT_EQ(csv[i][7], "");
      else
        EXPECT_EQ(float(value(csv[i][7])), props["speeds_ms"][i].get<float>());
      ++checked;
    }
  }
  EXPECT_GT(checked, 500u);
}

TEST_F(ExportEurope, TooManyPointsIs413BeforeAnyByte) {
  // The window's matching points, counted here by a plain loop with the window's own bounds.
  const TrailSet& set = *test_routes::europe_trails();
  const auto& p = set.points();
  std::uint64_t n = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    n += p.t[i] >= kT0 + 6 * 3600 && p.t[i] < kT0 + 12 * 3600 && p.alt[i] >= 10000 * 0.3048 &&
         p.alt[i] <= 30000 * 0.3048 && p.lat[i] >= 35 && p.lat[i] <= 60 && p.lon[i] >= -10 && p.lon[i] <= 30;
  const Response r = get("/api/v1/datasets/eu/export", window({{"format", "csv"}, {"max_points", "1000"}}));
  expect_error(r, 413, "payload_too_large", "max_points");
  EXPECT_FALSE(r.stream);
  EXPECT_EQ(body(r)["detail"], "the window holds " + std::to_string(n) +
                                   " points, more than max_points=1000: narrow the window or the filters");
  // Exactly n fits.
  const Response ok =
      get("/api/v1/datasets/eu/export", window({{"format", "csv"}, {"max_points", std::to_string(n)}}));
  ASSERT_EQ(ok.status, 200);
  EXPECT_EQ(lines(ok.collect()).size(), n + 1);
}

TEST_F(ExportEurope, SummaryCsvTablesEqualTheJson) {
  const auto j = body(get("/api/v1/datasets/eu/summary", window()));
  const auto table = [&](const std::string& name) {
    const Response r = get("/api/v1/datasets/eu/summary", window({{"format", "csv"}, {"table", name}}));
    EXPECT_EQ(r.status, 200) << r.body;
    EXPECT_EQ(r.content_type, "text/csv; charset=utf-8");
    EXPECT_EQ(header(r, "Content-Disposition"), "attachment; filename=\"eu-summary-" + name + ".csv\"");
    std::vector<std::vector<std::string>> out;
    for (const auto& l : lines(r.body)) out.push_back(csv_fields(l));
    return out;
  };
  const auto totals = table("totals");
  ASSERT_EQ(totals[0], (std::vector<std::string>{"key", "value"}));
  std::map<std::string, double> kv;
  for (std::size_t i = 1; i < totals.size(); ++i) kv[totals[i][0]] = std::stod(totals[i][1]);
  EXPECT_EQ(kv.at("flights"), j["flights"].get<double>());
  EXPECT_EQ(kv.at("points"), j["points"].get<double>());
  EXPECT_EQ(kv.at("t_min"), j["t_min"].get<double>());
  EXPECT_EQ(kv.at("t_max"), j["t_max"].get<double>());
  EXPECT_EQ(kv.at("speed_count"), j["speed"]["count"].get<double>());
  EXPECT_EQ(kv.at("speed_mean_ms"), j["speed"]["mean"].get<double>());
  EXPECT_EQ(kv.at("speed_p95_ms"), j["speed"]["p95"].get<double>());
  EXPECT_EQ(kv.at("speed_max_ms"), j["speed"]["max"].get<double>());
  const auto time = table("time_histogram");
  ASSERT_EQ(time.size(), j["time_histogram"]["counts"].size() + 1);
  for (std::size_t i = 1; i < time.size(); ++i) {
    const double t0 = j["time_histogram"]["t0"].get<double>() +
                      double(i - 1) * j["time_histogram"]["bin_seconds"].get<double>();
    EXPECT_EQ(std::stod(time[i][0]), t0);
    EXPECT_EQ(std::stoull(time[i][2]), j["time_histogram"]["counts"][i - 1].get<std::uint64_t>());
  }
  const auto alt = table("altitude_histogram");
  ASSERT_EQ(alt.size(), j["altitude_histogram"]["counts"].size() + 1);
  for (std::size_t i = 1; i < alt.size(); ++i) {
    EXPECT_EQ(alt[i][2], "ft");
    EXPECT_EQ(std::stoull(alt[i][3]), j["altitude_histogram"]["counts"][i - 1].get<std::uint64_t>());
  }
  const auto top = table("top_callsigns");
  ASSERT_EQ(top.size(), j["top_callsigns"].size() + 1);
  for (std::size_t i = 1; i < top.size(); ++i) {
    EXPECT_EQ(top[i][0], j["top_callsigns"][i - 1]["callsign"]);
    EXPECT_EQ(std::stoull(top[i][2]), j["top_callsigns"][i - 1]["points"].get<std::uint64_t>());
  }
}

// Hand-made rows: quoting, unknown values, the refusals.
class ExportHand : public test_routes::RouteFixture {
 protected:
  ExportHand() {
    TrailSetBuilder b;
    Sample s;
    s.t = kT0, s.lat = 50.5f, s.lon = 8.25f, s.alt = 1000, s.speed = 100;
    b.add("abc123", "AB\"C,1", s);
    s.t = kT0 + 10, s.alt = Sample::kUnknown, s.speed = Sample::kUnknown, s.on_ground = true;
    b.add("abc123", "AB\"C,1", s);
    auto ds = std::make_shared<Dataset>();
    ds->id = "hand", ds->name = "hand", ds->format = "test", ds->created = "2026-01-01T00:00:00Z";
    ds->trails = std::make_shared<const TrailSet>(b.build());
    open(ds);
  }
  void expect_detail(const Response& r, int status, const std::string& param, const std::string& detail) {
    expect_error(r, status, status == 400 ? "invalid_argument" : "not_found", param);
    EXPECT_EQ(body(r)["detail"], detail) << r.body;
  }
};

TEST_F(ExportHand, CsvRowsQuotedAndUnknownsEmpty) {
  const Response r = get("/api/v1/datasets/hand/export", {{"format", "csv"}});
  ASSERT_EQ(r.status, 200) << r.body;
  const auto callsign =
      body(get("/api/v1/datasets/hand/flights"))["flights"][0]["callsign"].get<std::string>();
  ASSERT_NE(callsign.find(','), std::string::npos);
  std::string quoted = "\"";
  for (char c : callsign) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  quoted += "\"";
  const std::string text = r.collect();  // a streamed body is drawn once
  EXPECT_EQ(text,
            "flight_id,icao24,callsign,t,lat,lon,alt_m,speed_ms,track_deg,vrate_ms,on_ground\n"
            "0,abc123," +
                quoted +
                ",1514764800,50.5,8.25,1000,100,,,0\n"
                "0,abc123," +
                quoted + ",1514764810,50.5,8.25,,,,,1\n");
  EXPECT_EQ(csv_fields(lines(text).at(1))[2], callsign);
  // An empty window: the header alone; GeoJSON: no features.
  const Response none = get("/api/v1/datasets/hand/export", {{"format", "csv"}, {"t0", "0"}, {"t1", "1"}});
  EXPECT_EQ(none.collect(),
            "flight_id,icao24,callsign,t,lat,lon,alt_m,speed_ms,track_deg,vrate_ms,on_ground\n");
  const auto empty =
      nlohmann::json::parse(get("/api/v1/datasets/hand/export", {{"t0", "0"}, {"t1", "1"}}).collect());
  EXPECT_TRUE(empty["features"].empty());
  EXPECT_EQ(empty["points"], 0);
}

TEST_F(ExportHand, Refusals) {
  expect_detail(get("/api/v1/datasets/hand/export", {{"format", "kml"}}), 400, "format",
                "format must be 'geojson' or 'csv', got 'kml'");
  expect_detail(get("/api/v1/datasets/hand/export", {{"max_points", "0"}}), 400, "max_points",
                "max_points must lie in 1..10000000, got 0");
  expect_detail(get("/api/v1/datasets/hand/export", {{"page", "1"}}), 400, "page",
                body(get("/api/v1/datasets/hand/summary", {{"page", "1"}}))["detail"]);
  expect_detail(get("/api/v1/datasets/nope/export"), 404, "dataset",
                body(get("/api/v1/datasets/nope"))["detail"]);
  expect_detail(get("/api/v1/datasets/hand/summary", {{"format", "xml"}}), 400, "format",
                "format must be 'json' or 'csv', got 'xml'");
  expect_detail(get("/api/v1/datasets/hand/summary", {{"format", "csv"}, {"table", "speeds"}}), 400, "table",
                "table must be one of totals, time_histogram, altitude_histogram, top_callsigns, quality, "
                "got 'speeds'");
  expect_detail(get("/api/v1/datasets/hand/summary", {{"table", "totals"}}), 400, "table",
                "table applies to format=csv only (the JSON holds every table)");
}

}  // namespace
}  // namespace trailscope::server
