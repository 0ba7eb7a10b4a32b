// The demo traffic generator: determinism, volume, sampling, physical plausibility, airports at both ends.
#include <gtest/gtest.h>

#include <GeographicLib/Geodesic.hpp>

#include <chrono>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

#include "ingest_test_helpers.hpp"
#include "trailscope/ingest/demo_traffic.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::ingest {
namespace {

std::filesystem::path vega_data() {
  return test::source_dir() / "web/node_modules/vega-datasets/data";
}

DemoOptions options(std::size_t flights, std::uint64_t seed = 42) {
  DemoOptions o;
  o.airports_csv = (vega_data() / "airports.csv").string();
  o.routes_csv = (vega_data() / "flights-airport.csv").string();
  o.flights = flights;
  o.seed = seed;
  return o;
}

#define REQUIRE_VEGA()                                        \
  if (!std::filesystem::exists(vega_data() / "airports.csv")) \
  GTEST_SKIP() << "vega-datasets not installed (cd web && npm install): " << vega_data()

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

bool same_columns(const TrailSet& a, const TrailSet& b) {
  const PointColumns &p = a.points(), &q = b.points();
  return same_bytes(p.t, q.t) && same_bytes(p.lat, q.lat) && same_bytes(p.lon, q.lon) &&
         same_bytes(p.alt, q.alt) && same_bytes(p.speed, q.speed) && same_bytes(p.track, q.track) &&
         same_bytes(p.vrate, q.vrate) && same_bytes(p.on_ground, q.on_ground);
}

/// `set`'s samples fed one by one through TrailSetBuilder, the path every ingested file takes; the
/// generator writes its columns directly, and must give what the builder would (no duplicate, no split).
TrailSet through_the_builder(const TrailSet& set) {
  TrailSetBuilder b;
  const PointColumns& p = set.points();
  for (const Flight& f : set.flights())
    for (std::uint32_t i = f.begin; i < f.end; ++i) {
      Sample s;
      s.t = p.t[i], s.lat = p.lat[i], s.lon = p.lon[i], s.alt = p.alt[i];
      s.speed = p.speed[i], s.track = p.track[i], s.vrate = p.vrate[i], s.on_ground = p.on_ground[i] != 0;
      b.add(f.icao24, f.callsign, s);
    }
  TrailSetBuilder::Stats stats;
  TrailSet built = b.build(&stats);
  EXPECT_EQ(stats.duplicates, 0u);
  EXPECT_EQ(stats.splits, 0u);
  return built;
}

TEST(DemoTraffic, SameSeedSameBytesOtherSeedDiffers) {
  REQUIRE_VEGA();
  const TrailSet a = generate_demo_traffic(options(500));
  const TrailSet b = generate_demo_traffic(options(500));
  const TrailSet c = generate_demo_traffic(options(500, 43));
  EXPECT_EQ(a.num_flights(), 500u);
  EXPECT_TRUE(same_columns(a, b));
  for (std::size_t i = 0; i < a.num_flights(); ++i) {
    EXPECT_EQ(a.flights()[i].icao24, b.flights()[i].icao24);
    EXPECT_EQ(a.flights()[i].callsign, b.flights()[i].callsign);
  }
  EXPECT_FALSE(same_columns(a, c));
}

// The generator builds its TrailSet directly (for speed); TrailSetBuilder must give the very same set.
TEST(DemoTraffic, SameAsThroughTheBuilder) {
  REQUIRE_VEGA();
  const TrailSet direct = generate_demo_traffic(options(400, 7));
  const TrailSet built = through_the_builder(direct);
  test::expect_same_trails(direct, built);
  for (std::size_t k = 0; k < direct.num_flights(); ++k) {
    const Flight &x = direct.flights()[k], &y = built.flights()[k];
    EXPECT_EQ(x.t_min, y.t_min);
    EXPECT_EQ(x.t_max, y.t_max);
    EXPECT_EQ(x.lat_min, y.lat_min);
    EXPECT_EQ(x.lat_max, y.lat_max);
    EXPECT_EQ(x.lon_min, y.lon_min);
    EXPECT_EQ(x.lon_max, y.lon_max);
    EXPECT_EQ(x.alt_min, y.alt_min);
    EXPECT_EQ(x.alt_max, y.alt_max);
    EXPECT_EQ(x.crosses_antimeridian, y.crosses_antimeridian);
  }
  EXPECT_EQ(direct.t_min(), built.t_min());
  EXPECT_EQ(direct.lon_max(), built.lon_max());
}

// Airports as the generator reads them, for the end-point checks.
std::vector<std::pair<double, double>> airports() {
  std::ifstream in(vega_data() / "airports.csv");
  std::string line;
  std::getline(in, line);
  std::vector<std::pair<double, double>> out;
  while (std::getline(in, line)) {
    // The last two fields are latitude, longitude (names may contain quoted commas before them).
    const auto c2 = line.rfind(','), c1 = line.rfind(',', c2 - 1);
    out.emplace_back(std::stod(line.substr(c1 + 1, c2 - c1 - 1)), std::stod(line.substr(c2 + 1)));
  }
  return out;
}

double nearest_airport_m(const std::vector<std::pair<double, double>>& ap, double lat, double lon) {
  double best = 1e300;
  for (const auto& [a, o] : ap) {
    if (std::fabs(a - lat) > 0.5 || std::fabs(o - lon) > 0.7) continue;  // cheap prefilter (> 30 km away)
    double s12;
    GeographicLib::Geodesic::WGS84().Inverse(lat, lon, a, o, s12);
    best = std::min(best, s12);
  }
  return best;
}

TEST(DemoTraffic, DefaultDayIsPlausible) {
  REQUIRE_VEGA();
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::pair<double, std::string>> progress;
  const DemoOptions opts = options(DemoOptions{}.flights);
  const TrailSet set =
      generate_demo_traffic(opts, [&](double f, std::string_view s) { progress.emplace_back(f, s); });
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::cout << "[ demo    ] " << set.num_flights() << " flights, " << set.num_points() << " points in "
            << seconds << " s\n";
  EXPECT_GE(set.num_flights(), 20000u);
  EXPECT_GT(set.num_points(), 5'000'000u);
  ASSERT_FALSE(progress.empty());
  EXPECT_EQ(progress.back(), (std::pair<double, std::string>{1.0, "assemble"}));

  const PointColumns& p = set.points();
  const auto ap = airports();
  std::array<int, 24> departures_by_utc_hour{};
  float max_alt = 0, max_speed = 0;
  std::size_t cruise_points = 0, cruise_in_range = 0;
  for (std::size_t fi = 0; fi < set.num_flights(); ++fi) {
    const Flight& f = set.flights()[fi];
    ASSERT_GE(f.size(), 20u);
    ASSERT_EQ(f.icao24.size(), 6u);
    ASSERT_GE(f.icao24, "a00001");
    ASSERT_LE(f.icao24, "adf7c7");
    ASSERT_GE(f.callsign.size(), 4u);
    ASSERT_TRUE(p.on_ground[f.begin] && p.on_ground[f.end - 1]) << "taxi at both ends, flight " << fi;
    ASSERT_GE(f.t_min, opts.day_start);
    ASSERT_LT(f.t_min, opts.day_start + 86400);
    ++departures_by_utc_hour[static_cast<int>((f.t_min - opts.day_start) / 3600)];
    for (std::uint32_t i = f.begin + 1; i < f.end; ++i) {
      const double dt = p.t[i] - p.t[i - 1];
      ASSERT_GE(dt, 5.0 - 1e-6) << fi;
      ASSERT_LE(dt, 10.0 + 1e-6) << fi;
    }
    for (std::uint32_t i = f.begin; i < f.end; ++i) {
      max_alt = std::max(max_alt, p.alt[i]);
      max_speed = std::max(max_speed, p.speed[i]);
      ASSERT_FALSE(std::isnan(p.alt[i]) || std::isnan(p.speed[i]) || std::isnan(p.track[i]));
      if (p.on_ground[i]) {
        ASSERT_EQ(p.alt[i], 0.0f);
        ASSERT_LE(p.speed[i], 80.0f);  // taxi, or the take-off/landing roll (< 160 kt)
      }
      if (p.alt[i] > 9000 && std::fabs(p.vrate[i]) < 0.01f) {  // level above FL295: cruise
        ++cruise_points;
        cruise_in_range += p.speed[i] >= 440 * 0.5144f && p.speed[i] <= 480 * 0.5145f;
      }
    }
    if (fi < 2000) {  // ends within 10 km of an airport (the geodesic check is slow, so on a subset)
      EXPECT_LT(nearest_airport_m(ap, p.lat[f.begin], p.lon[f.begin]), 10000) << fi;
      EXPECT_LT(nearest_airport_m(ap, p.lat[f.end - 1], p.lon[f.end - 1]), 10000) << fi;
    }
  }
  EXPECT_LE(max_alt, 39000 * 0.3048f + 1);  // FL390 at most (≤ 13 km)
  EXPECT_GE(max_alt, 37000 * 0.3048f);
  EXPECT_LE(max_speed, 480 * 0.5145f);
  EXPECT_GT(cruise_points, set.num_points() / 5);
  EXPECT_GT(cruise_in_range, cruise_points * 95 / 100);
  // US night (08–10 UTC = 03–05 EST) is much quieter than the afternoon (18–20 UTC).
  EXPECT_LT(departures_by_utc_hour[8] + departures_by_utc_hour[9],
            (departures_by_utc_hour[18] + departures_by_utc_hour[19]) / 3);
}

TEST(DemoTraffic, BadOptionsAndMissingInputs) {
  DemoOptions o = options(10);
  o.flights = 0;
  auto e = test::catch_error([&] { generate_demo_traffic(o); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->param(), "flights");
  o = options(10);
  o.sample_max_s = 1;
  e = test::catch_error([&] { generate_demo_traffic(o); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->param(), "sample_max_s");
  o = options(10);
  o.airports_csv = "/nonexistent/airports.csv";
  e = test::catch_error([&] { generate_demo_traffic(o); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->kind(), Error::Kind::not_found);
  EXPECT_EQ(e->param(), "airports_csv");

  test::TempDir dir;
  test::write_text(dir.path() / "a.csv", "iata,latitude,longitude\nAAA,40,-74\nBBB,34,-118\n");
  test::write_text(dir.path() / "r.csv", "from,to,count\nAAA,BBB,3\n");
  o.airports_csv = (dir.path() / "a.csv").string();
  o.routes_csv = (dir.path() / "r.csv").string();
  e = test::catch_error([&] { generate_demo_traffic(o); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->kind(), Error::Kind::unprocessable);
  EXPECT_EQ(e->param(), "routes_csv");

  // A minimal valid pair of inputs works without vega-datasets.
  test::write_text(dir.path() / "r.csv", "origin,destination,count\nAAA,BBB,3\nBBB,AAA,1\nAAA,ZZZ,5\n");
  const TrailSet set = generate_demo_traffic(o);
  EXPECT_EQ(set.num_flights(), 10u);
}

// Fleet mode: aircraft flying leg after leg over several days.
DemoOptions fleet_options(std::size_t aircraft, int days, std::uint64_t seed = 42) {
  DemoOptions o = options(1, seed);
  o.aircraft = aircraft, o.days = days;
  o.sample_min_s = 30, o.sample_max_s = 90;
  return o;
}

TEST(DemoFleet, SameSeedSameBytesAndSameAsThroughTheBuilder) {
  REQUIRE_VEGA();
  const TrailSet a = generate_demo_traffic(fleet_options(120, 2));
  const TrailSet b = generate_demo_traffic(fleet_options(120, 2));
  const TrailSet c = generate_demo_traffic(fleet_options(120, 2, 43));
  EXPECT_TRUE(same_columns(a, b));
  EXPECT_FALSE(same_columns(a, c));
  test::expect_same_trails(a, through_the_builder(a));
}

TEST(DemoFleet, AircraftFlyLegAfterLegInsideTheDays) {
  REQUIRE_VEGA();
  DemoOptions o = fleet_options(300, 3, 5);
  const TrailSet set = generate_demo_traffic(o);
  const double start = o.day_start, end = o.day_start + 3 * 86400.0;
  const PointColumns& p = set.points();
  for (double t : p.t) ASSERT_TRUE(t >= start && t < end) << t;
  // Legs by aircraft, in time order.
  std::map<std::string, std::vector<const Flight*>> by_aircraft;
  for (const Flight& f : set.flights()) {
    EXPECT_GE(f.size(), 2u);
    by_aircraft[f.icao24].push_back(&f);
  }
  EXPECT_EQ(by_aircraft.size(), 300u);
  std::size_t interior = 0;
  for (auto& [icao, legs] : by_aircraft) {
    std::sort(legs.begin(), legs.end(), [](auto* x, auto* y) { return x->t_min < y->t_min; });
    for (std::size_t k = 1; k < legs.size(); ++k) {
      const Flight &prev = *legs[k - 1], &next = *legs[k];
      EXPECT_NE(prev.callsign, next.callsign);
      // Never two legs at once; the gate time in between.
      EXPECT_GE(next.t_min - prev.t_max, o.turnaround_min_s) << icao;
      // The next leg leaves from where the last one ended: taxi-in, then taxi-out and the take-off roll,
      // all within a few km of the airport reference point.
      double gap_m;
      GeographicLib::Geodesic::WGS84().Inverse(p.lat[prev.end - 1], p.lon[prev.end - 1], p.lat[next.begin],
                                               p.lon[next.begin], gap_m);
      EXPECT_LT(gap_m, 12000) << icao << " leg " << k;
      ++interior;
    }
  }
  EXPECT_GT(interior, 300u * 3);
  // In flight (or taxiing) at mid-time: at most one leg per aircraft, most of the fleet.
  const double mid = start + 1.5 * 86400;
  std::size_t now = 0;
  for (const Flight& f : set.flights()) now += f.t_min <= mid && mid <= f.t_max;
  EXPECT_LE(now, 300u);
  EXPECT_GE(now, 150u);
}

TEST(DemoFleet, BadOptions) {
  DemoOptions o = fleet_options(10, 2);
  o.aircraft = kMaxDemoAircraft + 1;
  auto e = test::catch_error([&] { generate_demo_traffic(o); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->param(), "aircraft");
  o = fleet_options(10, 0);
  e = test::catch_error([&] { generate_demo_traffic(o); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->param(), "days");
  o = fleet_options(10, kMaxDemoDays + 1);
  e = test::catch_error([&] { generate_demo_traffic(o); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->param(), "days");
  o = fleet_options(10, 1);
  o.turnaround_min_s = 100, o.turnaround_max_s = 50;
  e = test::catch_error([&] { generate_demo_traffic(o); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->param(), "turnaround");
}

}  // namespace
}  // namespace trailscope::ingest
