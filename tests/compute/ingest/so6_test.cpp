// SO6 m3: the Europe day against an independent count, and the segment → point rules on a small fixture.
#include <gtest/gtest.h>

#include <GeographicLib/Geodesic.hpp>

#include <ctime>
#include <iterator>
#include <set>
#include <sstream>
#include <unordered_map>

#include "ingest_test_helpers.hpp"
#include "trailscope/ingest/ingest.hpp"

namespace trailscope::ingest {
namespace {

// hhmmss + yymmdd (20yy) → Unix seconds, written independently of the reader.
double so6_time(const std::string& hhmmss, const std::string& yymmdd) {
  std::tm tm{};
  tm.tm_year = 100 + std::stoi(yymmdd.substr(0, 2));
  tm.tm_mon = std::stoi(yymmdd.substr(2, 2)) - 1;
  tm.tm_mday = std::stoi(yymmdd.substr(4, 2));
  tm.tm_hour = std::stoi(hhmmss.substr(0, 2));
  tm.tm_min = std::stoi(hhmmss.substr(2, 2));
  tm.tm_sec = std::stoi(hhmmss.substr(4, 2));
  return static_cast<double>(timegm(&tm));
}

TEST(So6, EuropeDay) {
  const auto path = test::shared_data("flights/traffic_europe_20180101_m3.so6.gz");
  // Independent reading: every segment contributes its begin and end time to its flight; the TrailSet
  // must hold one point per distinct (flight_id, time).
  std::istringstream in(test::read_all(path));
  std::string line;
  std::set<std::pair<std::string, double>> distinct;
  std::set<std::string> flight_ids, callsigns;
  std::size_t segments = 0;
  while (std::getline(in, line)) {
    std::istringstream f(line);
    std::vector<std::string> v{std::istream_iterator<std::string>(f), {}};
    ASSERT_EQ(v.size(), 20u) << line;
    ++segments;
    flight_ids.insert(v[16]);
    callsigns.insert(v[9]);
    distinct.emplace(v[16], so6_time(v[4], v[10]));
    distinct.emplace(v[16], so6_time(v[5], v[11]));
  }
  EXPECT_EQ(segments, 127672u);  // SOURCES.md
  EXPECT_EQ(flight_ids.size(), 11043u);

  IngestReport rep;
  const TrailSet set = ingest_file(path.string(), {}, &rep);
  EXPECT_EQ(rep.format, Format::so6);
  EXPECT_EQ(rep.rows, segments);
  EXPECT_EQ(rep.rejected, 0u);
  // One flight per flight id, and one more per split between two legs or at a teleport (split by default;
  // the split count itself is checked against the rule in tests/server/quality_test.cpp).
  EXPECT_GT(rep.leg_splits.count, 0u);
  EXPECT_EQ(set.num_flights(), 11043u + rep.leg_splits.count + rep.jump_splits.count);
  EXPECT_EQ(set.num_points(), distinct.size());
  EXPECT_EQ(rep.points, distinct.size());

  std::set<std::string> seen_callsigns;
  for (const Flight& f : set.flights()) {
    EXPECT_TRUE(f.icao24.empty());
    seen_callsigns.insert(f.callsign);
  }
  EXPECT_EQ(seen_callsigns, callsigns);  // callsigns are unique per flight here, so no "/flight_id" suffix

  const double day0 = 1514764800;  // 2018-01-01T00:00:00Z
  const PointColumns& p = set.points();
  std::size_t fast = 0, unknown_speed = 0;
  for (std::size_t i = 0; i < set.num_points(); ++i) {
    ASSERT_GE(p.t[i], day0);
    ASSERT_LT(p.t[i], day0 + 86400);
    ASSERT_GE(p.lat[i], 30.0f);
    ASSERT_LE(p.lat[i], 65.0f);
    ASSERT_GE(p.lon[i], -15.0f);
    ASSERT_LE(p.lon[i], 40.0f);
    ASSERT_FALSE(std::isnan(p.alt[i]));
    ASSERT_FALSE(p.speed[i] > 1500) << i;  // impossible legs are NaN, not numbers
    fast += p.speed[i] > 350;              // > 680 kt: only the data's own glitches
    unknown_speed += std::isnan(p.speed[i]);
  }
  EXPECT_LT(fast, set.num_points() / 100);
  EXPECT_LT(unknown_speed, set.num_points() / 50);

  // First segment of AAF154: DAAG→LFPO, 18:10:10, FL339, lat 2303.9016723659997', lon 234.41902323'.
  const auto it = std::find_if(set.flights().begin(), set.flights().end(),
                               [](const Flight& f) { return f.callsign == "AAF154"; });
  ASSERT_NE(it, set.flights().end());
  const std::size_t i = it->begin;
  EXPECT_EQ(p.t[i], day0 + 18 * 3600 + 10 * 60 + 10);
  EXPECT_FLOAT_EQ(p.lat[i], static_cast<float>(2303.9016723659997 / 60));
  EXPECT_FLOAT_EQ(p.lon[i], static_cast<float>(234.41902323 / 60));
  EXPECT_FLOAT_EQ(p.alt[i], static_cast<float>(339 * 100 * 0.3048));
  // Speed and track from the geodesic to the segment's end (18:35:40, FL357).
  double s12, azi1, azi2;
  GeographicLib::Geodesic::WGS84().Inverse(
      static_cast<float>(2303.9016723659997 / 60), static_cast<float>(234.41902323 / 60),
      static_cast<float>(2478.798522948 / 60), static_cast<float>(273.9624023436 / 60), s12, azi1, azi2);
  EXPECT_NEAR(p.speed[i], s12 / 1530, 1e-3);
  EXPECT_NEAR(p.track[i], azi1 < 0 ? azi1 + 360 : azi1, 1e-3);
  EXPECT_NEAR(p.vrate[i], (357 - 339) * 100 * 0.3048 / 1530, 1e-4);
}

TEST(So6, SegmentsBecomeOrderedPointsAndSharedCallsignsStayApart) {
  test::TempDir dir;
  // Flight 1 (AAA1) listed out of order, sharing endpoints; flight 2 reuses callsign AAA1 → suffixed.
  // Line 4 has 19 fields, line 5 a bad time, line 6 a latitude beyond 90°.
  test::write_text(dir.path() / "f.so6",
                   "A_B A B A320 100100 100200 100 200 0 AAA1 180101 180101 3000 600 3010 610 1 0 0 0\n"
                   "A_B A B A320 100000 100100 0 100 0 AAA1 180101 180101 2990 590 3000 600 1 0 0 0\n"
                   "C_D C D B738 120000 121000 300 300 0 AAA1 180101 180101 3000 0 3000 60 2 0 0 0\n"
                   "C_D C D B738 121000 122000 300 300 0 AAA1 180101 180101 3000 60 3000 0 2 0 0\n"
                   "C_D C D B738 1210x0 122000 300 300 0 AAA1 180101 180101 3000 60 3000 0 2 0 0 0\n"
                   "C_D C D B738 121000 122000 300 300 0 AAA1 180101 180101 5500 60 3000 0 2 0 0 0\n"
                   "\n"
                   "E_F E F B738 000100 004000 300 300 0 BBB2 180101 180101 3000 60 3000 0 3 0 0 0\n");
  IngestReport rep;
  const TrailSet set = ingest_file((dir.path() / "f.so6").string(), {}, &rep);
  EXPECT_EQ(rep.format, Format::so6);
  EXPECT_EQ(rep.rows, 7u);
  ASSERT_EQ(rep.rejects.size(), 3u);
  EXPECT_EQ(rep.rejects[0].line, 4u);
  EXPECT_NE(rep.rejects[0].reason.find("20 space-separated fields"), std::string::npos);
  EXPECT_EQ(rep.rejects[1].line, 5u);
  EXPECT_NE(rep.rejects[1].reason.find("bad begin time"), std::string::npos);
  EXPECT_EQ(rep.rejects[2].line, 6u);
  EXPECT_NE(rep.rejects[2].reason.find("latitude out of range"), std::string::npos);

  ASSERT_EQ(set.num_flights(), 3u);
  std::unordered_map<std::string, const Flight*> by;
  for (const Flight& f : set.flights()) by[f.callsign] = &f;
  ASSERT_TRUE(by.count("AAA1/1") && by.count("AAA1/2") && by.count("BBB2"));
  const Flight& f1 = *by["AAA1/1"];
  ASSERT_EQ(f1.size(), 3u);  // 10:00:00, 10:01:00, 10:02:00
  const PointColumns& p = set.points();
  EXPECT_EQ(p.t[f1.begin + 1] - p.t[f1.begin], 60.0);
  EXPECT_FLOAT_EQ(p.alt[f1.begin], 0.0f);
  EXPECT_FLOAT_EQ(p.alt[f1.begin + 2], 200 * 30.48f);
  EXPECT_NEAR(p.vrate[f1.begin], 100 * 30.48 / 60, 1e-4);
  EXPECT_NEAR(p.vrate[f1.begin + 2], 100 * 30.48 / 60, 1e-4);  // last point: the arriving leg
  // A 39-minute segment does not split the flight (no gap splitting for SO6).
  EXPECT_EQ(by["BBB2"]->size(), 2u);
  EXPECT_EQ(by["AAA1/2"]->size(), 2u);
  EXPECT_NEAR(p.track[by["AAA1/2"]->begin], 90, 0.5);  // due east along 50°N
}

}  // namespace
}  // namespace trailscope::ingest
