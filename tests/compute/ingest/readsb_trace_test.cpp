// readsb trace_full: base time + dt, "ground" altitudes, knots and ft/min, callsigns carried forward
// from the details objects; checked against counts computed here from the raw JSON.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>

#include <nlohmann/json.hpp>

#include "ingest_test_helpers.hpp"
#include "trailscope/ingest/ingest.hpp"

namespace trailscope::ingest {
namespace {

using nlohmann::json;

const char* kTrace = "flights/traffic_sample_trace_full_ac671b.json";

std::string flight_of(const json& row) {
  if (row.size() <= 8 || !row[8].is_object() || !row[8].contains("flight") || !row[8]["flight"].is_string())
    return "";
  std::string f = row[8]["flight"].get<std::string>();
  f.erase(f.find_last_not_of(' ') + 1);
  return f;
}

TEST(ReadsbTrace, MatchesAnIndependentReading) {
  const json doc = json::parse(test::read_all(test::shared_data(kTrace)));
  const json& trace = doc["trace"];
  ASSERT_EQ(trace.size(), 2500u);
  const double base = doc["timestamp"].get<double>();

  // Callsign per row: the latest details "flight", the first one for rows before any.
  std::string current;
  for (const json& row : trace)
    if (!(current = flight_of(row)).empty()) break;
  std::map<std::string, std::vector<double>> by_callsign;
  std::size_t ground_rows = 0;
  for (const json& row : trace) {
    if (const std::string f = flight_of(row); !f.empty()) current = f;
    by_callsign[current].push_back(base + row[0].get<double>());
    ground_rows += row[3].is_string();
  }
  std::size_t points = 0, flights = 0;
  for (auto& [cs, times] : by_callsign) {
    std::sort(times.begin(), times.end());
    times.erase(std::unique(times.begin(), times.end()), times.end());
    points += times.size();
    ++flights;
    for (std::size_t k = 1; k < times.size(); ++k) flights += times[k] - times[k - 1] > 1800;
  }
  EXPECT_EQ(by_callsign.size(), 4u);  // DAL1812, DAL1615, DAL2927, DAL2418

  IngestReport rep;
  const TrailSet set = ingest_file(test::shared_data(kTrace).string(), {}, &rep);
  EXPECT_EQ(rep.format, Format::readsb_trace);
  EXPECT_EQ(rep.rows, 2500u);
  EXPECT_EQ(rep.rejected, 0u);
  EXPECT_EQ(set.num_points(), points);
  EXPECT_EQ(rep.duplicates, 2500u - points);
  EXPECT_EQ(set.num_flights(), flights);
  std::size_t ground = 0, ground_nan = 0;
  for (std::size_t i = 0; i < set.num_points(); ++i)
    if (set.points().on_ground[i]) ++ground, ground_nan += std::isnan(set.points().alt[i]);
  EXPECT_EQ(ground, ground_nan);  // no altitude on the ground
  EXPECT_NEAR(static_cast<double>(ground), static_cast<double>(ground_rows),
              1.0);  // one duplicate time may drop one
  for (const Flight& f : set.flights()) {
    EXPECT_EQ(f.icao24, "ac671b");
    EXPECT_EQ(f.callsign.substr(0, 3), "DAL");
  }

  // First row: [0.0, 16.777359, -88.036868, 32000, 478.6, 327.8, 1, 0, null, ...]; its callsign comes from
  // the details of row 4 ("DAL1812 ").
  const Flight& first = set.flights().front();
  EXPECT_EQ(first.callsign, "DAL1812");
  const PointColumns& p = set.points();
  const std::size_t i = first.begin;
  EXPECT_DOUBLE_EQ(p.t[i], 1738703622.619);
  EXPECT_FLOAT_EQ(p.lat[i], 16.777359f);
  EXPECT_FLOAT_EQ(p.lon[i], -88.036868f);
  EXPECT_FLOAT_EQ(p.alt[i], 32000 * 0.3048f);
  EXPECT_NEAR(p.speed[i], 478.6 * 1852.0 / 3600.0, 1e-3);
  EXPECT_FLOAT_EQ(p.track[i], 327.8f);
  EXPECT_FLOAT_EQ(p.vrate[i], 0.0f);
  EXPECT_EQ(p.on_ground[i], 0);
  // Row 3 (index 2) has geom_rate 32 but baro_rate 0: the barometric rate wins.
  EXPECT_FLOAT_EQ(p.vrate[i + 2], 0.0f);
}

TEST(ReadsbTrace, RowsWithoutPositionOrWithBadAltitudeAreRejected) {
  test::TempDir dir;
  test::write_text(dir.path() / "t.json",
                   R"({"icao": "~a1b2c3", "timestamp": 1700000000, "trace": [
                        [0, 40.0, -74.0, "ground", 10, 90, 0, null, {"flight": null}, "adsb_icao", null, null, null, null],
                        [5, null, -74.0, 1000, 10, 90, 0, 500],
                        [10, 40.1, -74.1, "high", 10, 90, 0, 500],
                        "junk",
                        [null, 40.1, -74.1, 1000],
                        [20, 40.2, -74.2, 1000, 150, 90, 0, null, {"flight": "UAL1  "}, "adsb_icao", 1100, -640]
                      ]})");
  IngestReport rep;
  const TrailSet set = ingest_file((dir.path() / "t.json").string(), {}, &rep);
  EXPECT_EQ(rep.rows, 6u);
  ASSERT_EQ(rep.rejects.size(), 4u);
  EXPECT_EQ(rep.rejects[0].line, 2u);
  EXPECT_NE(rep.rejects[0].reason.find("missing position"), std::string::npos);
  EXPECT_EQ(rep.rejects[1].line, 3u);
  EXPECT_NE(rep.rejects[1].reason.find("bad altitude"), std::string::npos);
  EXPECT_EQ(rep.rejects[2].line, 4u);
  EXPECT_EQ(rep.rejects[3].line, 5u);
  EXPECT_NE(rep.rejects[3].reason.find("time missing"), std::string::npos);
  ASSERT_EQ(set.num_flights(), 1u);  // the first row takes the trace's first callsign
  EXPECT_EQ(set.flights()[0].icao24, "a1b2c3");
  EXPECT_EQ(set.flights()[0].callsign, "UAL1");
  ASSERT_EQ(set.num_points(), 2u);
  EXPECT_EQ(set.points().on_ground[0], 1);
  EXPECT_TRUE(std::isnan(set.points().alt[0]));
  EXPECT_TRUE(std::isnan(set.points().vrate[0]));
  EXPECT_FLOAT_EQ(set.points().vrate[1], -640 * 0.3048f / 60);  // geom_rate when baro_rate is null
}

}  // namespace
}  // namespace trailscope::ingest
