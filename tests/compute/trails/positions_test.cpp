// Positions at an instant on small synthetic flights whose answers are known in closed form: a sample
// exactly at t, interpolation, the antimeridian, track wrap, unknown values, presence at the ends, and
// filters that apply to the interpolated position rather than to the samples.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>

#include "trailscope/core/error.hpp"
#include "trailscope/trails/positions.hpp"
#include "trailscope/trails/query.hpp"
#include "trailscope/trails/summary.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope {
namespace {

constexpr float kNaNf = std::numeric_limits<float>::quiet_NaN();
constexpr std::size_t kCap = 1000;

Sample sample(double t, float lat, float lon, float alt = kNaNf, float speed = kNaNf, float track = kNaNf,
              float vrate = kNaNf, bool ground = false) {
  Sample s;
  s.t = t, s.lat = lat, s.lon = lon, s.alt = alt, s.speed = speed, s.track = track, s.vrate = vrate;
  s.on_ground = ground;
  return s;
}

// The position of the flight with this callsign, if it is in the answer (a copy: the answer is often a
// temporary).
std::optional<Position> find(const Positions& at, const std::string& callsign) {
  for (const Position& p : at.positions)
    if (p.callsign == callsign) return p;
  return std::nullopt;
}

// The position of the flight with this callsign; a failure (and NaN values) when it is absent.
Position the(const Positions& at, const std::string& callsign) {
  if (auto p = find(at, callsign)) return *p;
  ADD_FAILURE() << callsign << " is not in the answer at t = " << at.t;
  Position none;
  none.lat = none.lon = none.alt_m = none.speed_ms = none.track_deg = none.vrate_ms =
      std::numeric_limits<double>::quiet_NaN();
  return none;
}

Positions at(const TrailSet& set, double t, const std::map<std::string, std::string>& filters = {}) {
  return positions_at(set, t, parse_query(filters), kCap);
}

// "AAA1": t 1000 → 1100, every variable changing; the later sample's vertical rate is unknown.
// "GND1": on the ground at 1000, airborne from 1100.
TrailSet basic() {
  TrailSetBuilder b;
  b.add("aaaaaa", "AAA1", sample(1000, 10, 20, 1000, 100, 90, 5));
  b.add("aaaaaa", "AAA1", sample(1100, 11, 22, 2000, 200, 100, kNaNf));
  b.add("bbbbbb", "GND1", sample(1000, 50, 5, 0, 10, 45, 0, true));
  b.add("bbbbbb", "GND1", sample(1100, 50, 6, 300, 80, 45, 3, false));
  return b.build();
}

TEST(Positions, SampleExactlyAtTIsUsedAsIs) {
  const TrailSet set = basic();
  const Positions first = at(set, 1000);
  const std::optional<Position> p = find(first, "AAA1");
  ASSERT_TRUE(p.has_value());
  EXPECT_TRUE(p->exact);
  EXPECT_EQ(p->lat, 10.0);
  EXPECT_EQ(p->lon, 20.0);
  EXPECT_EQ(p->alt_m, 1000.0);
  EXPECT_EQ(p->speed_ms, 100.0);
  EXPECT_EQ(p->track_deg, 90.0);
  EXPECT_EQ(p->vrate_ms, 5.0);
  EXPECT_EQ(p->icao24, "aaaaaa");
  // The last sample: its unknown vertical rate stays unknown, the rest is the sample's.
  const std::optional<Position> q = find(at(set, 1100), "AAA1");
  ASSERT_TRUE(q.has_value());
  EXPECT_TRUE(q->exact);
  EXPECT_EQ(q->lat, 11.0);
  EXPECT_EQ(q->alt_m, 2000.0);
  EXPECT_TRUE(std::isnan(q->vrate_ms));
}

TEST(Positions, LinearInTimeBetweenTheBracketingSamples) {
  const TrailSet set = basic();
  const std::optional<Position> mid = find(at(set, 1050), "AAA1");
  ASSERT_TRUE(mid.has_value());
  EXPECT_FALSE(mid->exact);
  EXPECT_DOUBLE_EQ(mid->lat, 10.5);
  EXPECT_DOUBLE_EQ(mid->lon, 21.0);
  EXPECT_DOUBLE_EQ(mid->alt_m, 1500.0);
  EXPECT_DOUBLE_EQ(mid->speed_ms, 150.0);
  EXPECT_DOUBLE_EQ(mid->track_deg, 95.0);
  EXPECT_TRUE(std::isnan(mid->vrate_ms));  // unknown in the later sample
  const std::optional<Position> quarter = find(at(set, 1025), "AAA1");
  ASSERT_TRUE(quarter.has_value());
  EXPECT_DOUBLE_EQ(quarter->lat, 10.25);
  EXPECT_DOUBLE_EQ(quarter->lon, 20.5);
  EXPECT_DOUBLE_EQ(quarter->alt_m, 1250.0);
  // A fractional instant.
  const std::optional<Position> frac = find(at(set, 1000.5), "AAA1");
  ASSERT_TRUE(frac.has_value());
  EXPECT_NEAR(frac->lat, 10.005, 1e-12);
}

TEST(Positions, OnGroundComesFromTheEarlierSample) {
  const TrailSet set = basic();
  const std::optional<Position> p = find(at(set, 1099.9), "GND1");
  ASSERT_TRUE(p.has_value());
  EXPECT_TRUE(p->on_ground);
  EXPECT_FALSE(the(at(set, 1100), "GND1").on_ground);  // exactly at the airborne sample
  EXPECT_FALSE(find(at(set, 1050, {{"on_ground", "true"}}), "AAA1").has_value());
  EXPECT_TRUE(find(at(set, 1050, {{"on_ground", "true"}}), "GND1").has_value());
  EXPECT_FALSE(find(at(set, 1050, {{"on_ground", "false"}}), "GND1").has_value());
}

TEST(Positions, AbsentBeforeTheFirstAndAfterTheLastSample) {
  const TrailSet set = basic();
  EXPECT_TRUE(at(set, 999.999).positions.empty());
  EXPECT_TRUE(at(set, 1100.001).positions.empty());
  EXPECT_EQ(at(set, 1000).positions.size(), 2u);
  EXPECT_EQ(at(set, 1100).positions.size(), 2u);
  EXPECT_TRUE(at(TrailSet(), 1000).positions.empty());
}

TEST(Positions, LongitudeTakesTheShortestWayAcross180) {
  TrailSetBuilder b;
  b.add("eeeeee", "EAST", sample(0, 0, 179.5f));
  b.add("eeeeee", "EAST", sample(100, 0, -179.5f));
  b.add("ffffff", "WEST", sample(0, 10, -179.5f));
  b.add("ffffff", "WEST", sample(100, 10, 179.5f));
  const TrailSet set = b.build();
  EXPECT_DOUBLE_EQ(the(at(set, 25), "EAST").lon, 179.75);
  EXPECT_DOUBLE_EQ(the(at(set, 50), "EAST").lon, -180.0);  // 180 is written -180: [-180, 180)
  EXPECT_DOUBLE_EQ(the(at(set, 75), "EAST").lon, -179.75);
  EXPECT_DOUBLE_EQ(the(at(set, 25), "WEST").lon, -179.75);
  EXPECT_DOUBLE_EQ(the(at(set, 50), "WEST").lon, -180.0);
  EXPECT_DOUBLE_EQ(the(at(set, 75), "WEST").lon, 179.75);
  // Never through 0: a box around the Greenwich meridian sees neither flight at any instant.
  for (double t = 0; t <= 100; t += 5)
    EXPECT_TRUE(at(set, t, {{"bbox", "-170,-5,170,15"}}).positions.empty());
}

TEST(Positions, TrackTakesTheShortestArc) {
  TrailSetBuilder b;
  b.add("aaaaaa", "CW", sample(0, 0, 0, kNaNf, kNaNf, 350));
  b.add("aaaaaa", "CW", sample(100, 0, 1, kNaNf, kNaNf, 10));
  b.add("bbbbbb", "CCW", sample(0, 1, 0, kNaNf, kNaNf, 10));
  b.add("bbbbbb", "CCW", sample(100, 1, 1, kNaNf, kNaNf, 350));
  b.add("cccccc", "HALF", sample(0, 2, 0, kNaNf, kNaNf, 270));
  b.add("cccccc", "HALF", sample(100, 2, 1, kNaNf, kNaNf, 90));
  const TrailSet set = b.build();
  EXPECT_DOUBLE_EQ(the(at(set, 25), "CW").track_deg, 355.0);
  EXPECT_DOUBLE_EQ(the(at(set, 50), "CW").track_deg, 0.0);  // 360 is written 0: [0, 360)
  EXPECT_DOUBLE_EQ(the(at(set, 75), "CW").track_deg, 5.0);
  EXPECT_DOUBLE_EQ(the(at(set, 25), "CCW").track_deg, 5.0);
  EXPECT_DOUBLE_EQ(the(at(set, 75), "CCW").track_deg, 355.0);
  // Exactly opposite: clockwise, 270 → 360 → 90.
  EXPECT_DOUBLE_EQ(the(at(set, 25), "HALF").track_deg, 315.0);
  EXPECT_DOUBLE_EQ(the(at(set, 50), "HALF").track_deg, 0.0);
  for (double t = 0; t <= 100; t += 0.5)
    for (const Position& p : at(set, t).positions) {
      EXPECT_GE(p.track_deg, 0.0);
      EXPECT_LT(p.track_deg, 360.0);
    }
}

TEST(Positions, UnknownInEitherBracketIsUnknown) {
  TrailSetBuilder b;
  b.add("aaaaaa", "NAN1", sample(0, 0, 0, kNaNf, 100, 90, 1));
  b.add("aaaaaa", "NAN1", sample(10, 0, 1, 1000, kNaNf, kNaNf, 2));
  b.add("aaaaaa", "NAN1", sample(20, 0, 2, 2000, 120, 92, kNaNf));
  const TrailSet set = b.build();
  Position p = the(at(set, 5), "NAN1");
  EXPECT_TRUE(std::isnan(p.alt_m));
  EXPECT_TRUE(std::isnan(p.speed_ms));
  EXPECT_TRUE(std::isnan(p.track_deg));
  EXPECT_DOUBLE_EQ(p.vrate_ms, 1.5);
  p = the(at(set, 15), "NAN1");
  EXPECT_DOUBLE_EQ(p.alt_m, 1500.0);
  EXPECT_TRUE(std::isnan(p.speed_ms));
  EXPECT_TRUE(std::isnan(p.vrate_ms));
  // At the middle sample itself: its own values, unknown speed included.
  p = the(at(set, 10), "NAN1");
  EXPECT_EQ(p.alt_m, 1000.0);
  EXPECT_TRUE(std::isnan(p.speed_ms));
  EXPECT_EQ(p.vrate_ms, 2.0);
  // Unknown altitude fails an altitude band, even where the samples' altitudes would pass it.
  EXPECT_TRUE(at(set, 5, {{"alt_min", "0"}, {"alt_unit", "m"}}).positions.empty());
  EXPECT_EQ(at(set, 15, {{"alt_min", "0"}, {"alt_unit", "m"}}).positions.size(), 1u);
}

TEST(Positions, FiltersApplyToTheInterpolatedPosition) {
  TrailSetBuilder b;
  // Outside the box at both samples, inside it at t = 50 (lon 5).
  b.add("aaaaaa", "THRU", sample(0, 0, 0, 0));
  b.add("aaaaaa", "THRU", sample(100, 0, 10, 10000));
  // Inside a box spanning [-179.5, 179.5] at both samples (179 and -179), outside it at t = 50, where
  // the shortest way passes 180.
  b.add("bbbbbb", "WRAP", sample(0, 0, 179, 5000));
  b.add("bbbbbb", "WRAP", sample(100, 0, -179, 5000));
  const TrailSet set = b.build();
  const std::map<std::string, std::string> box = {{"bbox", "4,-1,6,1"}};
  EXPECT_TRUE(at(set, 0, box).positions.empty());
  EXPECT_TRUE(at(set, 100, box).positions.empty());
  ASSERT_EQ(at(set, 50, box).positions.size(), 1u);
  EXPECT_EQ(at(set, 50, box).positions[0].callsign, "THRU");
  EXPECT_TRUE(at(set, 30, box).positions.empty());  // lon 3
  // Box edges are inside, as for samples (PointFilter).
  EXPECT_EQ(at(set, 40, box).positions.size(), 1u);  // lon 4
  EXPECT_EQ(at(set, 60, box).positions.size(), 1u);  // lon 6
  // Altitude band 4000–6000 m: THRU is at 0 and 10000 m at its samples, 5000 m at t = 50.
  const std::map<std::string, std::string> band = {
      {"alt_min", "4000"}, {"alt_max", "6000"}, {"alt_unit", "m"}};
  EXPECT_FALSE(find(at(set, 0, band), "THRU").has_value());
  EXPECT_TRUE(find(at(set, 50, band), "THRU").has_value());
  EXPECT_FALSE(find(at(set, 70, band), "THRU").has_value());  // 7000 m
  // The antimeridian case, both ways round.
  const std::map<std::string, std::string> world = {{"bbox", "-179.5,-1,179.5,1"}};
  EXPECT_TRUE(find(at(set, 0, world), "WRAP").has_value());
  EXPECT_TRUE(find(at(set, 100, world), "WRAP").has_value());
  EXPECT_FALSE(find(at(set, 50, world), "WRAP").has_value());
  EXPECT_TRUE(find(at(set, 50, {{"bbox", "179.5,-1,-179.5,1"}}), "WRAP").has_value());  // a box across 180
  EXPECT_FALSE(find(at(set, 0, {{"bbox", "179.5,-1,-179.5,1"}}), "WRAP").has_value());
}

TEST(Positions, FlightFiltersAndOrderByFlightId) {
  TrailSetBuilder b;
  // Added out of order; the builder orders flights by start time, then icao24.
  b.add("cccccc", "EZY12", sample(30, 1, 1));
  b.add("cccccc", "EZY12", sample(200, 1, 2));
  b.add("aaaaaa", "RYR1", sample(10, 2, 1));
  b.add("aaaaaa", "RYR1", sample(200, 2, 2));
  b.add("bbbbbb", "RYR22", sample(20, 3, 1));
  b.add("bbbbbb", "RYR22", sample(200, 3, 2));
  const TrailSet set = b.build();
  const Positions all = at(set, 100);
  ASSERT_EQ(all.positions.size(), 3u);
  for (std::size_t i = 0; i < all.positions.size(); ++i) {
    const Position& p = all.positions[i];
    EXPECT_EQ(p.flight_id, i);  // every flight matches, so ids are 0, 1, 2
    EXPECT_EQ(set.flights()[p.flight_id].callsign, p.callsign);
    EXPECT_EQ(set.flights()[p.flight_id].icao24, p.icao24);
  }
  // The ids are the flight list's.
  const FlightPage page = list_flights(set, Query{}, 0, 10);
  for (const FlightRow& r : page.flights) EXPECT_EQ(all.positions[r.id].callsign, r.callsign);
  EXPECT_EQ(at(set, 100, {{"callsign", "RYR"}}).positions.size(), 2u);
  EXPECT_EQ(at(set, 100, {{"callsign", "ryr?"}}).positions.size(), 1u);
  EXPECT_EQ(at(set, 100, {{"callsign", "*12"}}).positions.size(), 1u);
  const Positions by_icao = at(set, 100, {{"icao24", "CCCCCC,bbbbbb"}});
  ASSERT_EQ(by_icao.positions.size(), 2u);
  EXPECT_LT(by_icao.positions[0].flight_id, by_icao.positions[1].flight_id);
}

TEST(Positions, FlightsAreTheStoresFlightsSplitAtTheGap) {
  TrailSetBuilder b;
  // 1000 s apart: one flight, interpolated across the gap. 4000 s apart: two flights (limit 1800 s).
  b.add("aaaaaa", "NEAR", sample(0, 0, 0));
  b.add("aaaaaa", "NEAR", sample(1000, 0, 10));
  b.add("bbbbbb", "FAR", sample(0, 1, 0));
  b.add("bbbbbb", "FAR", sample(4000, 1, 10));
  const TrailSet set = b.build();
  ASSERT_EQ(set.num_flights(), 3u);
  EXPECT_DOUBLE_EQ(the(at(set, 500), "NEAR").lon, 5.0);
  EXPECT_FALSE(find(at(set, 2000), "FAR").has_value());
  EXPECT_TRUE(find(at(set, 4000), "FAR").has_value());
}

TEST(Positions, RefusesAWindowAndBadInstants) {
  const TrailSet set = basic();
  const auto param_of = [&](double t, const std::map<std::string, std::string>& filters) -> std::string {
    try {
      positions_at(set, t, parse_query(filters), kCap);
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), Error::Kind::invalid_argument);
      EXPECT_NE(std::string(e.what()).find("instant"), std::string::npos) << e.what();
      return e.param();
    }
    return "";
  };
  EXPECT_EQ(param_of(1000, {{"t0", "900"}}), "t0");
  EXPECT_EQ(param_of(1000, {{"t1", "1100"}}), "t1");
  EXPECT_EQ(param_of(1000, {{"t0", "900"}, {"t1", "1100"}}), "t0");
  EXPECT_EQ(param_of(std::numeric_limits<double>::quiet_NaN(), {}), "t");
  EXPECT_EQ(param_of(std::numeric_limits<double>::infinity(), {}), "t");
}

TEST(Positions, MoreThanTheCapIsRefused) {
  const TrailSet set = basic();
  EXPECT_EQ(positions_at(set, 1050, Query{}, 2).positions.size(), 2u);
  try {
    positions_at(set, 1050, Query{}, 1);
    FAIL() << "expected payload_too_large";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::payload_too_large);
    EXPECT_EQ(e.param(), "max_positions");
    EXPECT_EQ(std::string(e.what()),
              "2 flights match at t, more than max_positions=1; narrow the answer with bbox, "
              "alt_min/alt_max, callsign or icao24");
  }
  // The cap counts matches after the filters.
  EXPECT_EQ(positions_at(set, 1050, parse_query({{"callsign", "AAA"}}), 1).positions.size(), 1u);
}

TEST(Positions, JsonAndGeoJson) {
  const TrailSet set = basic();
  const Positions p = at(set, 1050);
  const nlohmann::json j = p.to_json();
  EXPECT_EQ(j["t"], 1050.0);
  EXPECT_EQ(j["count"], 2);
  ASSERT_EQ(j["positions"].size(), 2u);
  const nlohmann::json& a = j["positions"][0]["callsign"] == "AAA1" ? j["positions"][0] : j["positions"][1];
  EXPECT_EQ(a["lat"], 10.5);
  EXPECT_EQ(a["lon"], 21.0);
  EXPECT_EQ(a["alt_m"], 1500.0);
  EXPECT_TRUE(a["vrate_ms"].is_null());
  EXPECT_EQ(a["exact"], false);
  EXPECT_EQ(a["on_ground"], false);
  const nlohmann::json g = p.to_geojson();
  EXPECT_EQ(g["type"], "FeatureCollection");
  EXPECT_EQ(g["count"], 2);
  ASSERT_EQ(g["features"].size(), 2u);
  for (const auto& f : g["features"]) {
    EXPECT_EQ(f["geometry"]["type"], "Point");
    if (f["properties"]["callsign"] != "AAA1") continue;
    EXPECT_EQ(f["geometry"]["coordinates"], nlohmann::json({21.0, 10.5}));  // [lon, lat]
    EXPECT_TRUE(f["properties"]["vrate_ms"].is_null());
    EXPECT_FALSE(f["properties"].contains("lat"));
  }
}

// At the scale of world traffic: 25,000 aircraft airborne at once (the world's peak is about 23,000), 60
// samples each; every one is found at every instant. (Speed is a benchmark's business, not a test's.)
TEST(Positions, TwentyFiveThousandAircraftAllFound) {
  constexpr int kFlights = 25000, kSamples = 60;
  TrailSetBuilder b;
  char icao[8];
  for (int f = 0; f < kFlights; ++f) {
    std::snprintf(icao, sizeof icao, "%06x", f);
    for (int k = 0; k < kSamples; ++k)
      b.add(icao, "SIM" + std::to_string(f),
            sample(1000.0 + (f % 97) + k * 60.0, -60.0f + (f % 120), -170.0f + (f % 340) + k * 0.05f, 10000,
                   230, 90, 0));
  }
  const TrailSet set = b.build();
  ASSERT_EQ(set.num_flights(), static_cast<std::size_t>(kFlights));
  std::size_t total = 0;
  for (int k = 0; k < 20; ++k)
    total += positions_at(set, 1200.0 + k * 150.3, Query{}, 100000).positions.size();
  EXPECT_EQ(total, 20u * kFlights);
}

}  // namespace
}  // namespace trailscope
