// traffic JSON records: the three real samples against counts computed here with nlohmann::json, unit
// conversions on known rows, JSON Lines and the lenient field forms.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <map>

#include <nlohmann/json.hpp>

#include "ingest_test_helpers.hpp"
#include "trailscope/ingest/ingest.hpp"

namespace trailscope::ingest {
namespace {

using nlohmann::json;
using test::shared_data;

struct Expected {
  std::size_t records = 0, points = 0, flights = 0, on_ground = 0, no_altitude = 0;
};

// What the TrailSet must hold, computed from the records directly: group by (icao24, callsign), keep the
// first record of each time, split at gaps > 1800 s.
Expected expected_from(const json& records) {
  struct Rec {
    double t;
    bool ground, no_alt;
  };
  std::map<std::pair<std::string, std::string>, std::vector<Rec>> groups;
  for (const json& r : records) {
    std::string cs = r["callsign"].is_string() ? r["callsign"].get<std::string>() : "";
    cs.erase(cs.find_last_not_of(' ') + 1);
    for (char& c : cs) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    const bool ground = r.contains("onground") && r["onground"].is_boolean() && r["onground"].get<bool>();
    groups[{r["icao24"].get<std::string>(), cs}].push_back(
        {r["timestamp"].get<double>() / 1000.0, ground, !r["altitude"].is_number()});
  }
  Expected e;
  e.records = records.size();
  for (auto& [key, recs] : groups) {
    std::stable_sort(recs.begin(), recs.end(), [](const Rec& a, const Rec& b) { return a.t < b.t; });
    double prev = -1e300;
    ++e.flights;
    for (const Rec& r : recs) {
      if (r.t == prev) continue;
      if (prev > -1e300 && r.t - prev > 1800) ++e.flights;
      prev = r.t;
      ++e.points;
      e.on_ground += r.ground;
      e.no_altitude += r.no_alt;
    }
  }
  return e;
}

void check_sample_file(const char* name, std::size_t records, std::size_t points) {
  const auto path = shared_data(std::string("flights/") + name);
  const json records_json = json::parse(test::read_all(path));
  const Expected e = expected_from(records_json);
  EXPECT_EQ(e.records, records);  // SOURCES.md
  EXPECT_EQ(e.points, points);

  IngestReport rep;
  const TrailSet set = ingest_file(path.string(), {}, &rep);
  EXPECT_EQ(rep.format, Format::traffic_json);
  EXPECT_EQ(rep.rows, e.records);
  EXPECT_EQ(rep.rejected, 0u);
  EXPECT_EQ(rep.points, e.points);
  EXPECT_EQ(set.num_points(), e.points);
  EXPECT_EQ(rep.duplicates, e.records - e.points);
  EXPECT_EQ(set.num_flights(), e.flights);
  std::size_t ground = 0, no_alt = 0;
  for (std::size_t i = 0; i < set.num_points(); ++i) {
    ground += set.points().on_ground[i];
    no_alt += std::isnan(set.points().alt[i]);
  }
  EXPECT_EQ(ground, e.on_ground);
  EXPECT_EQ(no_alt, e.no_altitude);
}

TEST(TrafficJson, Belevingsvlucht) {
  // One flight of 16,005 points with no gap over 30 min, so gap splitting leaves it whole.
  check_sample_file("traffic_sample_belevingsvlucht.json.gz", 16005, 16005);
  // A slow sightseeing flight whose position reports are noisy enough to show position jumps over 800 kt,
  // none of which is a teleport or a gap between legs: the default splitting leaves it whole.
  IngestReport rep;
  const TrailSet set =
      ingest_file(shared_data("flights/traffic_sample_belevingsvlucht.json.gz").string(), {}, &rep);
  ASSERT_EQ(set.num_flights(), 1u);
  EXPECT_GT(rep.quality.jumps.count, 100u);
  EXPECT_EQ(rep.jump_splits.count, 0u);
  EXPECT_EQ(rep.leg_splits.count, 0u);
  EXPECT_EQ(set.flights()[0].icao24, "484506");
  EXPECT_EQ(set.flights()[0].callsign, "TRA051");
  // First record: {"timestamp":1527693698000,"latitude":52.3239704714,"longitude":4.7394234794,
  //  "groundspeed":155.0,"track":3.0,"vertical_rate":2240.0,"altitude":224.0}
  const PointColumns& p = set.points();
  EXPECT_EQ(p.t[0], 1527693698.0);
  EXPECT_FLOAT_EQ(p.lat[0], 52.3239704714f);
  EXPECT_FLOAT_EQ(p.lon[0], 4.7394234794f);
  EXPECT_FLOAT_EQ(p.alt[0], 224.0f * 0.3048f);
  EXPECT_FLOAT_EQ(p.speed[0], 155.0f * 1852.0f / 3600.0f);
  EXPECT_FLOAT_EQ(p.track[0], 3.0f);
  EXPECT_FLOAT_EQ(p.vrate[0], 2240.0f * 0.3048f / 60.0f);
  EXPECT_EQ(set.t_max(), 1527711776.0);  // 2018-05-30 20:22:56Z
}

TEST(TrafficJson, AirbusTree) {
  check_sample_file("traffic_sample_airbus_tree.json.gz", 5412, 5412);
}

TEST(TrafficJson, ZurichAirportWithOnground) {
  // 17,132 records of which 2,298 repeat a time of the same aircraft; 10 ground movements.
  check_sample_file("traffic_sample_zurich_airport.json.gz", 17132, 14834);
  const TrailSet set = ingest_file(shared_data("flights/traffic_sample_zurich_airport.json.gz").string());
  EXPECT_EQ(set.num_flights(), 10u);
  // Points on the ground are on the airfield of LSZH (47.4647 N, 8.5492 E), but for a few OpenSky
  // glitches (onground set far away, in flight).
  std::size_t ground = 0, on_field = 0;
  for (std::size_t i = 0; i < set.num_points(); ++i)
    if (set.points().on_ground[i]) {
      ++ground;
      on_field +=
          std::fabs(set.points().lat[i] - 47.4647) < 0.03 && std::fabs(set.points().lon[i] - 8.5492) < 0.04;
    }
  EXPECT_GT(ground, 1000u);
  EXPECT_GT(on_field, ground * 95 / 100);
}

TEST(TrafficJson, JsonLinesIsoTimesNumericIcaoAndRejects) {
  test::TempDir dir;
  const auto file = dir.path() / "records.jsonl";
  test::write_text(
      file,
      "{\"timestamp\": \"2018-05-30T15:21:38Z\", \"icao24\": \"484506\", \"latitude\": 52.3, "
      "\"longitude\": 4.7, \"altitude\": 1000, \"callsign\": \"TRA051\", \"onground\": false}\n"
      "\n"
      "{\"timestamp\": \"2018-05-30T17:21:48.5+02:00\", \"icao24\": 484506, \"latitude\": 52.4, "
      "\"longitude\": 4.8, \"callsign\": \"TRA051\", \"extra\": {\"nested\": [1, 2]}}\n"
      "{\"timestamp\": 1527693710, \"icao24\": \"484506\", \"latitude\": null, \"longitude\": 4.8}\n"
      "{\"timestamp\": 1527693711000, \"icao24\": \"48450\", \"latitude\": 1, \"longitude\": 2}\n"
      "{\"timestamp\": 1527693712000, \"icao24\": \"484506\", \"latitude\": 1, \"longitude\": 2} x\n"
      "[1, 2]\n"
      "{\"icao24\": \"484506\", \"latitude\": 1, \"longitude\": 2}\n"
      "{\"timestamp\": 1527693713000, \"icao24\": \"484506\", \"latitude\": \"north\", \"longitude\": 2}\n"
      "{\"timestamp\": 1527693714000, \"icao24\": \"484506\", \"latitude\": 1, \"longitude\": 200}\n");
  IngestReport rep;
  const TrailSet set = ingest_file(file.string(), {}, &rep);
  EXPECT_EQ(rep.format, Format::traffic_json);
  EXPECT_EQ(rep.rows, 9u);
  EXPECT_EQ(rep.accepted, 2u);
  const std::vector<std::pair<std::size_t, std::string>> expected = {
      {4, "missing position"},       {5, "bad icao24 '48450'"}, {6, "invalid JSON"},
      {7, "not a JSON object"},      {8, "time missing"},       {9, "bad value for 'latitude'"},
      {10, "longitude out of range"}};
  ASSERT_EQ(rep.rejects.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(rep.rejects[i].line, expected[i].first);
    EXPECT_NE(rep.rejects[i].reason.find(expected[i].second), std::string::npos) << rep.rejects[i].reason;
  }
  ASSERT_EQ(set.num_flights(), 1u);
  ASSERT_EQ(set.num_points(), 2u);
  EXPECT_EQ(set.points().t[0], 1527693698.0);
  EXPECT_EQ(set.points().t[1], 1527693708.5);
  EXPECT_FLOAT_EQ(set.points().alt[0], 304.8f);
  EXPECT_TRUE(std::isnan(set.points().alt[1]));
}

TEST(TrafficJson, ArrayWithBadRecordsAndSyntaxError) {
  test::TempDir dir;
  test::write_text(
      dir.path() / "a.json",
      "[{\"timestamp\": 1527693698000, \"icao24\": \"484506\", \"latitude\": 52.3, \"longitude\": 4.7},"
      " 42, {\"timestamp\": 1527693699000, \"icao24\": \"484506\"}]");
  IngestReport rep;
  const TrailSet set = ingest_file((dir.path() / "a.json").string(), {}, &rep);
  EXPECT_EQ(rep.rows, 3u);
  ASSERT_EQ(rep.rejects.size(), 2u);
  EXPECT_EQ(rep.rejects[0].line, 2u);
  EXPECT_EQ(rep.rejects[1].line, 3u);
  EXPECT_EQ(set.num_points(), 1u);

  test::write_text(
      dir.path() / "b.json",
      "[{\"timestamp\": 1527693698000, \"icao24\": \"484506\", \"latitude\": 52.3, \"longitude\": 4.7},"
      " {\"timestamp\": 15276");
  const auto e = test::catch_error([&] { ingest_file((dir.path() / "b.json").string()); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->kind(), Error::Kind::unprocessable);
  EXPECT_NE(std::string(e->what()).find("invalid JSON after record 1"), std::string::npos) << e->what();
}

}  // namespace
}  // namespace trailscope::ingest
