// Losses of separation on synthetic cases with known answers. The expected figures come from formulas
// and from GeographicLib's geodesic distance (Karney, "Algorithms for geodesics", J. Geodesy 2013), never
// from separation.cpp's tangent plane: event ends are found by bisection on the geodesic distance.
#include <GeographicLib/Geodesic.hpp>

#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "trailscope/congestion/separation.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/trails/positions.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::congestion {
namespace {

constexpr double kT = 1514764800.0;  // 2018-01-01T00:00:00Z
constexpr double kFt = 0.3048;
const double kH = 5 * 1852.0;

struct Fix {
  double t;
  float lat, lon, alt;
  bool ground = false;
};

TrailSet make(const std::vector<std::pair<std::string, std::vector<Fix>>>& flights) {
  TrailSetBuilder b;
  int n = 0;
  for (const auto& [callsign, fixes] : flights) {
    char icao[7];
    std::snprintf(icao, sizeof icao, "%06x", 0xabc000 + n++);
    for (const Fix& f : fixes) {
      Sample s;
      s.t = f.t, s.lat = f.lat, s.lon = f.lon, s.alt = f.alt, s.on_ground = f.ground;
      b.add(icao, callsign, s);
    }
  }
  return b.build();
}

std::uint32_t id(const TrailSet& set, const std::string& callsign) {
  for (std::uint32_t i = 0; i < set.flights().size(); ++i)
    if (set.flights()[i].callsign == callsign) return i;
  ADD_FAILURE() << "no flight " << callsign;
  return 0;
}

Query window(double t0, double t1) {
  Query q;
  q.t0 = t0, q.t1 = t1;
  return q;
}

double geodesic(double lat1, double lon1, double lat2, double lon2) {
  double s = 0;
  GeographicLib::Geodesic::WGS84().Inverse(lat1, lon1, lat2, lon2, s);
  return s;
}

// Positions of two flights at t, from positions_at (trails/), and their geodesic distance.
struct Pair {
  Position a, b;
  double d;
};
Pair at(const TrailSet& set, std::uint32_t fa, std::uint32_t fb, double t) {
  const Positions p = positions_at(set, t, Query{}, 1'000'000);
  Pair r{};
  int found = 0;
  for (const Position& x : p.positions) {
    if (x.flight_id == fa) r.a = x, ++found;
    if (x.flight_id == fb) r.b = x, ++found;
  }
  EXPECT_EQ(found, 2) << "at t=" << t;
  r.d = geodesic(r.a.lat, r.a.lon, r.b.lat, r.b.lon);
  return r;
}

// The instant in [lo, hi] where f changes sign, by bisection (f(lo) and f(hi) of opposite signs).
double bisect(const std::function<double(double)>& f, double lo, double hi) {
  const bool neg_lo = f(lo) < 0;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    ((f(mid) < 0) == neg_lo ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// Two level flights on parallels, head-on: A east along `lat_a` from lon c-1 to c+1, B west along
// `lat_b` from c+1 to c-1, both over [kT + t_first, kT + t_first + 1000]. They pass at kT + t_first + 500.
TrailSet head_on(float lat_a, float lat_b, float c, float alt_a, float alt_b, double t_first = 0) {
  const auto wrap = [](float lon) {
    return lon >= 180.0f ? lon - 360.0f : lon < -180.0f ? lon + 360.0f : lon;
  };
  return make(
      {{"AAA1",
        {{kT + t_first, lat_a, wrap(c - 1), alt_a}, {kT + t_first + 1000, lat_a, wrap(c + 1), alt_a}}},
       {"BBB2",
        {{kT + t_first, lat_b, wrap(c + 1), alt_b}, {kT + t_first + 1000, lat_b, wrap(c - 1), alt_b}}}});
}

// The geodesic ends of the head-on encounter: where the distance crosses 5 NM on either side of `mid`.
std::pair<double, double> geodesic_ends(const TrailSet& set, double mid, double reach) {
  const std::uint32_t a = id(set, "AAA1"), b = id(set, "BBB2");
  const auto f = [&](double t) { return at(set, a, b, t).d - kH; };
  return {bisect(f, mid - reach, mid), bisect(f, mid, mid + reach)};
}

TEST(Separation, HeadOnCpaMatchesGeodesic) {
  const float lat_b = 0.03125f;  // 1/32°: exact in float
  const TrailSet set = head_on(0, lat_b, 0, 9144, 9144);
  const SeparationResult r = losses_of_separation(set, window(kT, kT + 2000), {});
  ASSERT_EQ(r.events.size(), 1u);
  const SeparationEvent& e = r.events[0];
  const std::uint32_t a = id(set, "AAA1"), b = id(set, "BBB2");
  EXPECT_EQ(e.flight_a, std::min(a, b));
  EXPECT_EQ(e.flight_b, std::max(a, b));
  // CPA: the two pass each other at t = 500 s, on the meridian 0, one meridian arc of 1/32° apart.
  EXPECT_NEAR(e.cpa_t, kT + 500, 1e-6);
  EXPECT_NEAR(e.cpa_horizontal_m, geodesic(0, 0, lat_b, 0), 0.5);
  EXPECT_NEAR(e.cpa_vertical_m, 0, 1e-9);
  EXPECT_NEAR(e.cpa_lon_a, 0, 1e-9);
  EXPECT_NEAR(e.cpa_lat_b, lat_b, 1e-9);
  const auto [t_in, t_out] = geodesic_ends(set, kT + 500, 400);
  // Ends within 0.01 s of the geodesic ones (at 888 m/s of closure, 0.01 s is 9 m).
  EXPECT_NEAR(e.t_start, t_in, 0.01);
  EXPECT_NEAR(e.t_end, t_out, 0.01);
  EXPECT_FALSE(e.clipped_start);
  EXPECT_FALSE(e.clipped_end);
  EXPECT_EQ(r.pairs_with_events, 1u);
  EXPECT_EQ(r.flights, 2u);
  // Serialisations carry the same event.
  const nlohmann::json j = r.to_json();
  EXPECT_EQ(j["count"], 1);
  EXPECT_EQ(j["events"][0]["cpa"]["t"].get<double>(), e.cpa_t);
  EXPECT_EQ(j["events"][0]["callsign_a"], set.flights()[e.flight_a].callsign);
  const std::string csv = r.to_csv();
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 2);
  EXPECT_EQ(csv.rfind("flight_a,icao24_a,callsign_a,flight_b", 0), 0u);
}

// A grazing pass between two samples that lasts ~5.5 s and lies between two ticks of a 10 s clock.
TEST(Separation, ShortEventBetweenTenSecondTicksIsFound) {
  const float lat_b = 0.0830078125f;  // 85/1024°: ~9,180 m of meridian, just inside 5 NM
  const TrailSet set = head_on(0, lat_b, 0, 9144, 9144, 5);  // pass at t = 505 s
  const std::uint32_t a = id(set, "AAA1"), b = id(set, "BBB2");
  // A 10 s clock from kT sees no infringement at all.
  for (double t = kT + 10; t < kT + 1005; t += 10) EXPECT_GT(at(set, a, b, t).d, kH) << t - kT;
  const SeparationResult r = losses_of_separation(set, window(kT, kT + 2000), {});
  ASSERT_EQ(r.events.size(), 1u);
  const auto [t_in, t_out] = geodesic_ends(set, kT + 505, 100);
  EXPECT_GT(t_out - t_in, 4.0);
  EXPECT_LT(t_out - t_in, 7.0);
  EXPECT_GT(t_in, kT + 500);
  EXPECT_LT(t_out, kT + 510);
  EXPECT_NEAR(r.events[0].t_start, t_in, 0.01);
  EXPECT_NEAR(r.events[0].t_end, t_out, 0.01);
  EXPECT_NEAR(r.events[0].cpa_t, kT + 505, 1e-6);
  EXPECT_NEAR(r.events[0].cpa_horizontal_m, geodesic(0, 0, lat_b, 0), 0.5);
}

TEST(Separation, CrossingButVerticallySeparated) {
  // 1,200 ft apart: separated; 800 ft apart: a loss; both below FL410.
  EXPECT_TRUE(
      losses_of_separation(head_on(0, 0.03125f, 0, 9144, 9144 + 1200 * kFt), window(kT, kT + 2000), {})
          .events.empty());
  const SeparationResult r =
      losses_of_separation(head_on(0, 0.03125f, 0, 9144, 9144 + 800 * kFt), window(kT, kT + 2000), {});
  ASSERT_EQ(r.events.size(), 1u);
  EXPECT_NEAR(r.events[0].cpa_vertical_m, 800 * kFt, 1e-3);
  EXPECT_NEAR(r.events[0].min_vertical_m, 800 * kFt, 1e-3);
  // FL420 and FL435 (1,500 ft apart, above FL410): the 2,000 ft minimum applies.
  EXPECT_EQ(losses_of_separation(head_on(0, 0.03125f, 0, 42000 * kFt, 43500 * kFt), window(kT, kT + 2000), {})
                .events.size(),
            1u);
  // FL390 and FL405 (1,500 ft apart, below): separated.
  EXPECT_TRUE(
      losses_of_separation(head_on(0, 0.03125f, 0, 39000 * kFt, 40500 * kFt), window(kT, kT + 2000), {})
          .events.empty());
}

// In formation 1/32° (3.5 km) apart on parallels, B level at FL395, A climbing 10 ft/s from FL400: the
// gap is 500 ft + 10 ft/s · t. Below FL410 (t < 100 s) the minimum is 1,000 ft (infringed for t < 50 s);
// above it (A above FL410 from t = 100 s) 2,000 ft (infringed for t < 150 s): two events.
TEST(Separation, VerticalMinimumSwitchesAboveFl410) {
  const auto formation = [](float alt_b) {
    return make({{"AAA1", {{kT, 0, 0, 40000 * kFt}, {kT + 300, 0, 0.5f, 43000 * kFt}}},
                 {"BBB2", {{kT, 0.03125f, 0, alt_b}, {kT + 300, 0.03125f, 0.5f, alt_b}}}});
  };
  const TrailSet set = formation(39500 * kFt);
  const SeparationResult r = losses_of_separation(set, window(kT - 100, kT + 1000), {});
  ASSERT_EQ(r.events.size(), 2u);
  // The stored altitudes are floats: the instants move by < 1e-3 s.
  EXPECT_NEAR(r.events[0].t_start, kT, 1e-9);
  EXPECT_NEAR(r.events[0].t_end, kT + 50, 1e-3);
  EXPECT_NEAR(r.events[1].t_start, kT + 100, 1e-3);
  EXPECT_NEAR(r.events[1].t_end, kT + 150, 1e-3);
  EXPECT_NEAR(r.events[1].min_vertical_m, 1500 * kFt, 0.01);
  // B at FL405: the gap is -500 ft + 10 ft/s · t; A crosses FL410 at t = 100 s with the pair 500 ft
  // apart, inside both minima, so the event goes on across the switch: one event to t = 250 s (2,000 ft).
  const SeparationResult r2 = losses_of_separation(formation(40500 * kFt), window(kT - 100, kT + 1000), {});
  ASSERT_EQ(r2.events.size(), 1u);
  EXPECT_NEAR(r2.events[0].t_start, kT, 1e-9);
  EXPECT_NEAR(r2.events[0].t_end, kT + 250, 1e-3);
  EXPECT_NEAR(r2.events[0].min_vertical_m, 0, 1e-6);
  EXPECT_NEAR(r2.events[0].cpa_vertical_m, 500 * kFt, 0.01);  // the horizontal distance is constant: the
  EXPECT_NEAR(r2.events[0].cpa_t, kT, 1e-9);                  // earliest instant is the CPA
}

TEST(Separation, AcrossTheAntimeridian) {
  const float lat_b = 0.03125f;
  const TrailSet set = head_on(0, lat_b, 180.0f, 9144, 9144);  // A 179 → -179 eastwards, B the other way
  const SeparationResult r = losses_of_separation(set, window(kT, kT + 2000), {});
  ASSERT_EQ(r.events.size(), 1u);
  const SeparationEvent& e = r.events[0];
  EXPECT_NEAR(e.cpa_t, kT + 500, 1e-6);
  EXPECT_NEAR(e.cpa_horizontal_m, geodesic(0, 180, lat_b, 180), 0.5);
  EXPECT_GE(e.cpa_lon_a, -180.0);
  EXPECT_LT(e.cpa_lon_a, 180.0);
  EXPECT_NEAR(std::fabs(e.cpa_lon_a), 180.0, 1e-9);
  const auto [t_in, t_out] = geodesic_ends(set, kT + 500, 400);
  EXPECT_NEAR(e.t_start, t_in, 0.01);
  EXPECT_NEAR(e.t_end, t_out, 0.01);
  // The same encounter at 0° gives the same times.
  const SeparationResult r0 =
      losses_of_separation(head_on(0, lat_b, 0, 9144, 9144), window(kT, kT + 2000), {});
  ASSERT_EQ(r0.events.size(), 1u);
  EXPECT_NEAR(r0.events[0].t_start, e.t_start, 1e-4);
  EXPECT_NEAR(r0.events[0].t_end, e.t_end, 1e-4);
}

TEST(Separation, WindowClipsAndFiltersRestrict) {
  const TrailSet set = head_on(0, 0.03125f, 0, 9144, 9144);
  const SeparationResult full = losses_of_separation(set, window(kT, kT + 2000), {});
  ASSERT_EQ(full.events.size(), 1u);
  // A window that ends mid-event clips it.
  const SeparationResult clip = losses_of_separation(set, window(kT + 500, kT + 501), {});
  ASSERT_EQ(clip.events.size(), 1u);
  EXPECT_EQ(clip.events[0].t_start, kT + 500);
  EXPECT_EQ(clip.events[0].t_end, kT + 501);
  EXPECT_TRUE(clip.events[0].clipped_start);
  EXPECT_TRUE(clip.events[0].clipped_end);
  // bbox east edge at 0.01°: A (eastbound, 0.002°/s) is inside until t = 505 s, B (westbound) from
  // t = 495 s: the instants where both are inside are [495, 505].
  Query q = window(kT, kT + 2000);
  q.bbox = BBox{-5, -5, 0.01, 5};
  const SeparationResult box = losses_of_separation(set, q, {});
  ASSERT_EQ(box.events.size(), 1u);
  EXPECT_NEAR(box.events[0].t_start, kT + 495, 1e-3);
  EXPECT_NEAR(box.events[0].t_end, kT + 505, 1e-3);
  // The same box written across 180° (west > east) gives the same answer.
  q.bbox = BBox{170, -5, 0.01, 5};
  const SeparationResult wrap = losses_of_separation(set, q, {});
  ASSERT_EQ(wrap.events.size(), 1u);
  EXPECT_NEAR(wrap.events[0].t_start, kT + 495, 1e-3);
  // An altitude band above both: nothing. A callsign that selects one flight: no pair.
  q = window(kT, kT + 2000);
  q.alt_min = 10000;
  EXPECT_TRUE(losses_of_separation(set, q, {}).events.empty());
  q = window(kT, kT + 2000);
  q.callsign = "AAA";
  EXPECT_TRUE(losses_of_separation(set, q, {}).events.empty());
  q.callsign = "*";
  EXPECT_EQ(losses_of_separation(set, q, {}).events.size(), 1u);
}

TEST(Separation, GroundSegmentsAreNotAirborne) {
  // The same pass, with A's first sample on the ground: A's only segment touches the ground.
  const TrailSet set = make({{"AAA1", {{kT, 0, -1, 9144, true}, {kT + 1000, 0, 1, 9144}}},
                             {"BBB2", {{kT, 0.03125f, 1, 9144}, {kT + 1000, 0.03125f, -1, 9144}}}});
  EXPECT_TRUE(losses_of_separation(set, window(kT, kT + 2000), {}).events.empty());
}

TEST(Separation, BadInput) {
  const TrailSet set = head_on(0, 0.03125f, 0, 9144, 9144);
  const auto param = [&](const Query& q, const SeparationMinima& m) {
    try {
      losses_of_separation(set, q, m);
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), Error::Kind::invalid_argument);
      return e.param();
    }
    return std::string("(no error)");
  };
  Query q;
  EXPECT_EQ(param(q, {}), "t0");
  q.t0 = kT;
  EXPECT_EQ(param(q, {}), "t1");
  q.t1 = kT;
  EXPECT_EQ(param(q, {}), "t1");
  q.t1 = kT + 10;
  q.on_ground = true;
  EXPECT_EQ(param(q, {}), "on_ground");
  q.on_ground = false;
  EXPECT_EQ(param(q, {}), "(no error)");
  SeparationMinima m;
  m.horizontal_m = 0;
  EXPECT_EQ(param(q, m), "horizontal_m");
  m = {};
  m.vertical_m = NAN;
  EXPECT_EQ(param(q, m), "vertical_m");
  m = {};
  m.vertical_high_m = 100;
  EXPECT_EQ(param(q, m), "vertical_high_m");
  m = {};
  m.high_above_m = INFINITY;
  EXPECT_EQ(param(q, m), "high_above_m");
}

// The documented error of the tangent-plane distance: random encounters at |latitude| <= 70°, on long
// segments (10 min at 250 m/s: ~1.35° of latitude) with random headings; at every event's CPA the
// reported distance is within 3 m of the geodesic distance between the reported positions, and the CPA
// is the minimum of the geodesic distance around it within 5 m.
TEST(Separation, TangentPlaneErrorAgainstGeodesic) {
  std::mt19937_64 rng(20140101);
  std::uniform_real_distribution<double> U(0, 1);
  const auto& g = GeographicLib::Geodesic::WGS84();
  std::vector<std::pair<std::string, std::vector<Fix>>> flights;
  const int n = 200;
  for (int i = 0; i < n; ++i) {
    // Encounter i happens around t = 2000·i + 300: A passes (lat, lon) at 300 s, B passes a point up to
    // 4 NM away at the same instant, on another heading.
    const double lat = -70 + 140 * U(rng), lon = -180 + 360 * U(rng);
    const double ha = 360 * U(rng), hb = 360 * U(rng), v = 250;
    double off_lat, off_lon, lat0, lon0, lat1, lon1;
    g.Direct(lat, lon, 360 * U(rng), 4 * 1852.0 * U(rng), off_lat, off_lon);
    const double t = kT + 2000.0 * i;
    auto add = [&](const std::string& cs, double plat, double plon, double h) {
      g.Direct(plat, plon, h, -v * 300, lat0, lon0);
      g.Direct(plat, plon, h, v * 300, lat1, lon1);
      flights.push_back(
          {cs, {{t, float(lat0), float(lon0), 9000}, {t + 600, float(lat1), float(lon1), 9000}}});
    };
    add("A" + std::to_string(i), lat, lon, ha);
    add("B" + std::to_string(i), off_lat, off_lon, hb);
  }
  const TrailSet set = make(flights);
  const SeparationResult r = losses_of_separation(set, window(kT, kT + 2000.0 * n), {});
  ASSERT_EQ(r.events.size(), static_cast<std::size_t>(n));
  double worst = 0;
  for (const SeparationEvent& e : r.events) {
    const double d = geodesic(e.cpa_lat_a, e.cpa_lon_a, e.cpa_lat_b, e.cpa_lon_b);
    worst = std::max(worst, std::fabs(d - e.cpa_horizontal_m));
    const Pair p = at(set, e.flight_a, e.flight_b, e.cpa_t);
    EXPECT_NEAR(p.a.lat, e.cpa_lat_a, 1e-9);
    EXPECT_NEAR(p.b.lon, e.cpa_lon_b, 1e-9);
    for (double dt = -5; dt <= 5; dt += 0.5) {
      const double t = e.cpa_t + dt;
      if (t < e.t_start || t > e.t_end) continue;
      EXPECT_GE(at(set, e.flight_a, e.flight_b, t).d, d - 5.0);
    }
  }
  EXPECT_LT(worst, 3.0);
  RecordProperty("worst_error_m", std::to_string(worst));
}

}  // namespace
}  // namespace trailscope::congestion
