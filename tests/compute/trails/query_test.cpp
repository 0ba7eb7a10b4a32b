// Parsing of the airspace time-window query: every malformed parameter is an invalid_argument naming it.
#include <gtest/gtest.h>

#include "trailscope/core/error.hpp"
#include "trailscope/trails/query.hpp"
#include "trailscope/trails/summary.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope {
namespace {

std::string param_of(const std::map<std::string, std::string>& params) {
  try {
    parse_query(params);
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::invalid_argument);
    return e.param();
  }
  return "";
}

TEST(ParseTime, UnixAndIso) {
  EXPECT_DOUBLE_EQ(parse_time("1514764800", "t0"), 1514764800.0);
  EXPECT_DOUBLE_EQ(parse_time("1514764800.5", "t0"), 1514764800.5);
  EXPECT_DOUBLE_EQ(parse_time("2018-01-01", "t0"), 1514764800.0);
  EXPECT_DOUBLE_EQ(parse_time("2018-01-01T06:30:00Z", "t0"), 1514764800.0 + 6.5 * 3600);
  EXPECT_DOUBLE_EQ(parse_time("2018-01-01T06:30:00+01:00", "t0"), 1514764800.0 + 5.5 * 3600);
  EXPECT_DOUBLE_EQ(parse_time("2018-01-01T06:30:00.25-0200", "t0"), 1514764800.0 + 8.5 * 3600 + 0.25);
  EXPECT_DOUBLE_EQ(parse_time("2024-02-29T00:00Z", "t0"), 1709164800.0);  // leap day
  EXPECT_DOUBLE_EQ(parse_time("1969-12-31T23:59:59Z", "t0"), -1.0);
}

TEST(ParseQuery, ErrorsNameTheParameter) {
  EXPECT_EQ(param_of({{"bbox", "1,2,3"}}), "bbox");
  EXPECT_EQ(param_of({{"bbox", "a,2,3,4"}}), "bbox");
  EXPECT_EQ(param_of({{"bbox", "0,50,10,40"}}), "bbox");
  EXPECT_EQ(param_of({{"bbox", "-190,0,10,10"}}), "bbox");
  EXPECT_EQ(param_of({{"t0", "yesterday"}}), "t0");
  EXPECT_EQ(param_of({{"t0", "2018-13-01"}}), "t0");
  EXPECT_EQ(param_of({{"t0", "100"}, {"t1", "100"}}), "t1");
  EXPECT_EQ(param_of({{"t0", "0"}, {"t1", "40000000"}}), "t1");
  EXPECT_EQ(param_of({{"alt_min", "high"}}), "alt_min");
  EXPECT_EQ(param_of({{"alt_min", "3000"}, {"alt_max", "1000"}}), "alt_max");
  EXPECT_EQ(param_of({{"alt_unit", "km"}}), "alt_unit");
  EXPECT_EQ(param_of({{"icao24", "abc"}}), "icao24");
  EXPECT_EQ(param_of({{"icao24", "4ca1g0"}}), "icao24");
  EXPECT_EQ(param_of({{"callsign", "KLM;DROP"}}), "callsign");
  EXPECT_EQ(param_of({{"callsign", "ABCDEFGHIJKLMNOPQ"}}), "callsign");
  EXPECT_EQ(param_of({{"on_ground", "maybe"}}), "on_ground");
  EXPECT_EQ(param_of({{"bbox", "170,-10,-170,10"}, {"t0", "0"}, {"t1", "10"}}), "");  // crosses 180°: valid
}

TEST(ParseQuery, Normalises) {
  const Query m = parse_query({{"alt_min", "300"}, {"alt_max", "1000"}, {"alt_unit", "m"}});
  EXPECT_DOUBLE_EQ(*m.alt_min, 300);
  EXPECT_DOUBLE_EQ(*m.alt_max, 1000);
  const Query ft = parse_query({{"alt_min", "1000"}, {"alt_max", "2000"}});
  EXPECT_NEAR(*ft.alt_min, 304.8, 1e-9);
  EXPECT_NEAR(*ft.alt_max, 609.6, 1e-9);
  const Query ids = parse_query({{"icao24", "4CA1D0,4ca1d0,3c6444"}, {"callsign", "klm1*"}});
  EXPECT_EQ(ids.icao24, (std::vector<std::string>{"3c6444", "4ca1d0"}));
  EXPECT_EQ(ids.callsign, "KLM1*");
}

TEST(CallsignMatch, PrefixAndGlob) {
  EXPECT_TRUE(callsign_matches("KLM", "KLM1234"));
  EXPECT_FALSE(callsign_matches("KLM", "AKLM"));
  EXPECT_TRUE(callsign_matches("KLM*4", "KLM1234"));
  EXPECT_FALSE(callsign_matches("KLM*5", "KLM1234"));
  EXPECT_TRUE(callsign_matches("?LM12??", "KLM1234"));
  EXPECT_FALSE(callsign_matches("?LM12?", "KLM1234"));
  EXPECT_TRUE(callsign_matches("*", ""));
  EXPECT_TRUE(callsign_matches("*A*B*", "XAYBZ"));
}

TEST(Builder, SortsDedupsAndSplits) {
  TrailSetBuilder b;
  const auto s = [](double t, float lat) {
    Sample x;
    x.t = t, x.lat = lat, x.lon = 5, x.alt = 1000;
    return x;
  };
  b.add("ABC123", " klm1 ", s(30, 3));
  b.add("abc123", "KLM1", s(10, 1));
  b.add("abc123", "KLM1", s(20, 2));
  b.add("abc123", "KLM1", s(20, 9));    // duplicate time: the first one seen wins
  b.add("abc123", "KLM1", s(5000, 4));  // > 1800 s later: a new flight
  b.add("def456", "", s(15, 7));
  TrailSetBuilder::Stats st;
  const TrailSet t = b.build(&st);
  EXPECT_EQ(st.duplicates, 1u);
  EXPECT_EQ(st.splits, 1u);
  ASSERT_EQ(t.num_flights(), 3u);
  EXPECT_EQ(t.flights()[0].icao24, "abc123");
  EXPECT_EQ(t.flights()[0].callsign, "KLM1");
  EXPECT_EQ(t.flights()[0].size(), 3u);
  EXPECT_EQ(t.flights()[1].icao24, "def456");  // ordered by start time
  EXPECT_EQ(t.flights()[2].size(), 1u);
  EXPECT_EQ(t.points().lat[t.flights()[0].begin + 1], 2.0f);
  EXPECT_DOUBLE_EQ(t.t_min(), 10);
  EXPECT_DOUBLE_EQ(t.t_max(), 5000);
}

TEST(Summary, HistogramsAndSpeedOnKnownData) {
  TrailSetBuilder b;
  for (int i = 0; i < 100; ++i) {
    Sample x;
    x.t = 1000 + i * 10, x.lat = 50, x.lon = 4, x.alt = static_cast<float>(i * 30.48),
    x.speed = static_cast<float>(i);
    b.add("aaaaaa", "TEST1", x);
  }
  const TrailSet t = b.build();
  SummaryOptions o;
  o.bins = 10;
  const Summary s = summarize(t, parse_query({{"t0", "1000"}, {"t1", "2000"}}), o);
  EXPECT_EQ(s.points, 100u);
  EXPECT_EQ(s.flights, 1u);
  EXPECT_DOUBLE_EQ(s.time_histogram.bin_seconds, 120);  // 1000 s / 10 bins → the next nice width
  EXPECT_DOUBLE_EQ(s.time_histogram.t0, 960);
  ASSERT_EQ(s.altitude_histogram.counts.size(), 10u);  // 0..9900 ft in 1000 ft bins
  for (auto n : s.altitude_histogram.counts) EXPECT_EQ(n, 10u);
  EXPECT_DOUBLE_EQ(s.speed.mean, 49.5);
  EXPECT_NEAR(s.speed.p50, 49.5, 0.5);
  EXPECT_NEAR(s.speed.p95, 94.5, 0.5);
  EXPECT_EQ(s.top_callsigns.at(0).callsign, "TEST1");
  EXPECT_EQ(summarize(t, parse_query({{"on_ground", "true"}})).points, 0u);
}

}  // namespace
}  // namespace trailscope

namespace trailscope {
namespace {

// Regression (found by the garbage-parameter route test, 2026-11-22): a window with only t1, ending
// before the data starts, made the histogram size negative and threw out of summarize().
TEST(Summary, OneSidedWindowsOutsideTheData) {
  TrailSetBuilder b;
  for (int i = 0; i < 10; ++i) {
    Sample x;
    x.t = 1000 + i, x.lat = 1, x.lon = 1;
    b.add("aaaaaa", "A", x);
  }
  const TrailSet t = b.build();
  for (const auto& params : std::vector<std::map<std::string, std::string>>{
           {{"t1", "0"}}, {{"t1", "-0"}}, {{"t0", "5000"}}, {{"t1", "1000"}}}) {
    const Summary s = summarize(t, parse_query(params));
    EXPECT_EQ(s.points, 0u) << params.begin()->first << "=" << params.begin()->second;
    EXPECT_GE(s.time_histogram.counts.size(), 1u);
    EXPECT_LE(s.time_histogram.counts.size(), 97u);
  }
  EXPECT_EQ(summarize(t, parse_query({{"t0", "-1e300"}})).points, 10u);  // a vast one-sided window: one bin
  EXPECT_EQ(summarize(t, parse_query({{"t0", "1005"}})).points, 5u);
  EXPECT_EQ(summarize(t, parse_query({{"t1", "1005"}})).points, 5u);
}

}  // namespace
}  // namespace trailscope
