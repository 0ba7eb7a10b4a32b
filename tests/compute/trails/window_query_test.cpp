// Window queries on the real Europe SO6 day, checked against counts computed here from the raw file with
// code that shares nothing with the ingest or the query engine.

#include <cmath>
#include <map>
#include <set>
#include <tuple>

#include <gtest/gtest.h>

#include "so6_segments.hpp"
#include "test_support.hpp"
#include "trailscope/ingest/ingest.hpp"
#include "trailscope/trails/query.hpp"
#include "trailscope/trails/summary.hpp"

namespace trailscope {
namespace {

struct RawPoint {
  std::string flight;
  double t, lat, lon, alt_m;
};

// 2018-01-01T00:00:00Z; every row of the file is dated 180101.
constexpr double kDay = 1514764800.0;

// Distinct (flight_id, time) points from the segments' begin and end points.
const std::vector<RawPoint>& raw_points() {
  static const std::vector<RawPoint> pts = [] {
    std::map<std::pair<std::string, double>, RawPoint> uniq;
    for (const auto& s :
         test::read_so6_segments(test::shared_data("flights/traffic_europe_20180101_m3.so6.gz"), kDay)) {
      uniq.try_emplace({s.flight_id, s.t_begin},
                       RawPoint{s.flight_id, s.t_begin, s.lat_begin, s.lon_begin, s.alt_begin_m});
      uniq.try_emplace({s.flight_id, s.t_end},
                       RawPoint{s.flight_id, s.t_end, s.lat_end, s.lon_end, s.alt_end_m});
    }
    std::vector<RawPoint> v;
    for (auto& [k, p] : uniq) v.push_back(p);
    return v;
  }();
  return pts;
}

// The day's flights as the file delimits them (one per flight_id, split_jumps off): the counts here are by
// flight_id (the default split between legs and at teleports is checked in tests/server/quality_test.cpp).
const TrailSet& europe() {
  static const TrailSet set = [] {
    ingest::IngestOptions opts;
    opts.split_jumps = false;
    return ingest::ingest_file(test::shared_data("flights/traffic_europe_20180101_m3.so6.gz").string(), opts);
  }();
  return set;
}

struct Expected {
  std::uint64_t flights = 0, points = 0;
};

Expected count(double t0, double t1, const BBox& b, double alt_lo, double alt_hi) {
  std::set<std::string> flights;
  Expected e;
  for (const auto& p : raw_points()) {
    if (p.t < t0 || p.t >= t1) continue;
    if (p.lat < b.south || p.lat > b.north || p.lon < b.west || p.lon > b.east) continue;
    if (p.alt_m < alt_lo || p.alt_m > alt_hi) continue;
    ++e.points;
    flights.insert(p.flight);
  }
  e.flights = flights.size();
  return e;
}

TEST(WindowQuery, WholeDayHasAllFlightsAndPoints) {
  const Summary s = summarize(europe(), Query{});
  EXPECT_EQ(s.flights, 11043u);
  EXPECT_EQ(s.points, raw_points().size());
}

TEST(WindowQuery, WindowsMatchIndependentCounts) {
  struct Case {
    const char* bbox;
    const char* t0;
    const char* t1;
    const char* alt_min;
    const char* alt_max;
  };
  // Times as ISO 8601 and Unix seconds, altitudes in feet (the API's default unit).
  const Case cases[] = {
      {"-5,45,10,55", "2018-01-01T08:00:00Z", "2018-01-01T10:00:00Z", "0", "60000"},
      {"2,48,3,49.5", "1514786400", "1514808000", "10000", "30000"},
      {"-15,30,40,65", "2018-01-01T00:00:00Z", "2018-01-01T00:30:00Z", "30000", "45000"},
      {"20,35,30,45", "2018-01-01T12:00:00+01:00", "2018-01-01T18:00:00Z", "0", "9000"},
  };
  for (const Case& c : cases) {
    const Query q = parse_query(
        {{"bbox", c.bbox}, {"t0", c.t0}, {"t1", c.t1}, {"alt_min", c.alt_min}, {"alt_max", c.alt_max}});
    const Expected e = count(*q.t0, *q.t1, *q.bbox, *q.alt_min, *q.alt_max);
    const Summary s = summarize(europe(), q);
    SCOPED_TRACE(c.bbox);
    EXPECT_GT(e.points, 0u);
    EXPECT_EQ(s.points, e.points);
    EXPECT_EQ(s.flights, e.flights);
    std::uint64_t hist = 0;
    for (auto n : s.time_histogram.counts) hist += n;
    EXPECT_EQ(hist, e.points);
    const FlightPage page = list_flights(europe(), q, 0, 1000);
    EXPECT_EQ(page.total, e.flights);
  }
}

TEST(WindowQuery, CallsignFilters) {
  // AAF154 is the first flight of the file (DAAG → LFPO).
  const Query exact = parse_query({{"callsign", "aaf154"}});
  EXPECT_EQ(summarize(europe(), exact).flights, 1u);
  const Query prefix = parse_query({{"callsign", "AAF"}});
  const Query glob = parse_query({{"callsign", "AAF*"}});
  const auto a = summarize(europe(), prefix), b = summarize(europe(), glob);
  EXPECT_GE(a.flights, 1u);
  EXPECT_EQ(a.flights, b.flights);
  EXPECT_EQ(a.points, b.points);
  for (const auto& c : a.top_callsigns) EXPECT_EQ(c.callsign.rfind("AAF", 0), 0u);
}

}  // namespace
}  // namespace trailscope
