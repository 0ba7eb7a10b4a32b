// Positions at an instant on the real Europe SO6 day (11,043 flights), against two computations written
// here that share no code with positions.cpp:
//   1. a plain scan over every point of every flight of the ingested TrailSet (no binary search, no zone
//      map, the interpolation written differently): the same float inputs, so counts must be equal and
//      every interpolated value equal to 1e-9 (degrees, m, m/s: only the rounding of the double formulas
//      differs, ~1e-13 of the value);
//   2. the raw SO6 file read here (segment endpoints in decimal minutes and flight levels): counts equal,
//      positions within 1e-5° and altitudes within 2e-3 m, because the store keeps latitude, longitude
//      and altitude as float32 (half an ulp is 3.8e-6° below 128° of longitude, 7.6e-6° above, and
//      5e-4 m at 13 km), so an interpolation of the raw doubles differs by up to that.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "so6_segments.hpp"
#include "test_support.hpp"
#include "trailscope/ingest/ingest.hpp"
#include "trailscope/trails/positions.hpp"
#include "trailscope/trails/query.hpp"

namespace trailscope {
namespace {

constexpr double kDay = 1514764800.0;  // 2018-01-01T00:00:00Z; every row of the file is dated 180101
constexpr std::size_t kCap = 1'000'000;

std::filesystem::path so6_path() {
  return test::shared_data("flights/traffic_europe_20180101_m3.so6.gz");
}

const TrailSet& europe() {
  // The flights as the file delimits them (split_jumps off): the raw comparison below is by flight_id and
  // interpolates across the 20-hour gaps the default splitting cuts (tests/server/quality_test.cpp).
  static const TrailSet set = [] {
    ingest::IngestOptions opts;
    opts.split_jumps = false;
    return ingest::ingest_file(so6_path().string(), opts);
  }();
  return set;
}

class PositionsEurope : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(so6_path())) GTEST_SKIP() << so6_path() << " is absent";
  }
};

// The instants: midnight, whole seconds (where many SO6 samples lie exactly) and fractional ones.
const std::vector<double>& instants() {
  static const std::vector<double> v = {kDay,
                                        kDay + 6 * 3600,
                                        kDay + 8 * 3600,
                                        kDay + 12 * 3600 + 34 * 60 + 56.789,
                                        kDay + 17 * 3600 + 0.5,
                                        kDay + 23 * 3600 + 1800};
  return v;
}

// ---- 1. a plain scan over the TrailSet's points --------------------------------------------------------

struct Ref {
  double lat, lon, alt, speed, track, vrate;
  bool ground;
};

// Unknown stays NaN; (1 - w)·a + w·b is another formula than positions.cpp's a + (b - a)·w. Equal ends
// give that value exactly, as level flight must: a flight cruising at exactly FL300 sits on the edge of an
// FL100–FL300 band, and (1 - w)·a + w·a can round a hair above it.
double mix(double a, double b, double w) {
  if (std::isnan(a) || std::isnan(b)) return NAN;
  return a == b ? a : (1 - w) * a + w * b;
}

// Difference of two angles on the circle, in [-180, 180].
double circular(double a, double b) {
  return std::remainder(a - b, 360.0);
}

struct Window {
  const char* name;
  std::map<std::string, std::string> params;
};

// flight id → the reference position, for every flight present at t and matching the window.
std::map<std::uint32_t, Ref> scan(const TrailSet& set, double t, const Query& q) {
  const PointColumns& p = set.points();
  std::map<std::uint32_t, Ref> out;
  for (std::uint32_t fi = 0; fi < set.num_flights(); ++fi) {
    const Flight& f = set.flights()[fi];
    bool found = false;
    Ref r{};
    for (std::size_t i = f.begin; i < f.end && !found; ++i) {
      if (p.t[i] == t) {
        r = {p.lat[i], p.lon[i], p.alt[i], p.speed[i], p.track[i], p.vrate[i], p.on_ground[i] != 0};
        found = true;
      } else if (i + 1 < f.end && p.t[i] < t && t < p.t[i + 1]) {
        const double w = (t - p.t[i]) / (p.t[i + 1] - p.t[i]);
        r.lat = mix(p.lat[i], p.lat[i + 1], w);
        r.lon = std::remainder(p.lon[i] + w * circular(p.lon[i + 1], p.lon[i]), 360.0);
        r.alt = mix(p.alt[i], p.alt[i + 1], w);
        r.speed = mix(p.speed[i], p.speed[i + 1], w);
        const double dtrack = circular(p.track[i + 1], p.track[i]);
        r.track = std::isnan(dtrack) ? NAN : std::fmod(p.track[i] + w * dtrack + 720.0, 360.0);
        r.vrate = mix(p.vrate[i], p.vrate[i + 1], w);
        r.ground = p.on_ground[i] != 0;
        found = true;
      }
    }
    if (!found) continue;
    if (!q.icao24.empty() && std::find(q.icao24.begin(), q.icao24.end(), f.icao24) == q.icao24.end())
      continue;
    if (!q.callsign.empty() && f.callsign.rfind(q.callsign, 0) != 0) continue;  // the windows use prefixes
    if (q.bbox) {
      const BBox& b = *q.bbox;
      if (r.lat < b.south || r.lat > b.north || r.lon < b.west || r.lon > b.east) continue;
    }
    if ((q.alt_min && !(r.alt >= *q.alt_min)) || (q.alt_max && !(r.alt <= *q.alt_max))) continue;
    if (q.on_ground && r.ground != *q.on_ground) continue;
    out[fi] = r;
  }
  return out;
}

void expect_close(double got, double want, double tol, const char* what, std::uint32_t id) {
  if (std::isnan(want)) {
    EXPECT_TRUE(std::isnan(got)) << what << " of flight " << id << ": " << got << ", want unknown";
  } else {
    EXPECT_NEAR(got, want, tol) << what << " of flight " << id;
  }
}

TEST_F(PositionsEurope, EqualToAPlainScanAtSeveralInstantsAndWindows) {
  // No window; a box over western Europe; FL100–FL300; a callsign prefix; a small box with a band.
  const std::vector<Window> windows = {
      {"all", {}},
      {"bbox", {{"bbox", "-5,45,10,55"}}},
      {"band", {{"alt_min", "10000"}, {"alt_max", "30000"}}},
      {"callsign", {{"callsign", "RYR"}}},
      {"box+band", {{"bbox", "2,48,3,49.5"}, {"alt_min", "10000"}, {"alt_max", "30000"}}},
  };
  std::size_t compared = 0;
  for (const double t : instants())
    for (const Window& w : windows) {
      SCOPED_TRACE(std::string(w.name) + " at t = " + std::to_string(t));
      const Query q = parse_query(w.params);
      const std::map<std::uint32_t, Ref> want = scan(europe(), t, q);
      const Positions got = positions_at(europe(), t, q, kCap);
      ASSERT_EQ(got.positions.size(), want.size());
      if (w.params.empty() && t > kDay) EXPECT_GT(want.size(), 100u);
      for (const Position& p : got.positions) {
        const auto it = want.find(p.flight_id);
        ASSERT_NE(it, want.end()) << "flight " << p.flight_id << " is not present in the scan";
        const Ref& r = it->second;
        const Flight& f = europe().flights()[p.flight_id];
        EXPECT_EQ(p.callsign, f.callsign);
        EXPECT_EQ(p.icao24, f.icao24);
        expect_close(p.lat, r.lat, 1e-9, "lat", p.flight_id);
        EXPECT_NEAR(circular(p.lon, r.lon), 0.0, 1e-9) << "lon of flight " << p.flight_id;
        EXPECT_GE(p.lon, -180.0);
        EXPECT_LT(p.lon, 180.0);
        expect_close(p.alt_m, r.alt, 1e-9 * std::max(1.0, std::fabs(r.alt)), "alt_m", p.flight_id);
        expect_close(p.speed_ms, r.speed, 1e-9 * std::max(1.0, std::fabs(r.speed)), "speed_ms", p.flight_id);
        expect_close(p.vrate_ms, r.vrate, 1e-9 * std::max(1.0, std::fabs(r.vrate)), "vrate_ms", p.flight_id);
        if (std::isnan(r.track)) {
          EXPECT_TRUE(std::isnan(p.track_deg)) << "track of flight " << p.flight_id;
        } else {
          EXPECT_NEAR(circular(p.track_deg, r.track), 0.0, 1e-9) << "track of flight " << p.flight_id;
          EXPECT_GE(p.track_deg, 0.0);
          EXPECT_LT(p.track_deg, 360.0);
        }
        EXPECT_EQ(p.on_ground, r.ground);
        ++compared;
      }
      // Ordered by flight id.
      for (std::size_t i = 1; i < got.positions.size(); ++i)
        EXPECT_LT(got.positions[i - 1].flight_id, got.positions[i].flight_id);
    }
  EXPECT_GT(compared, 2000u);
}

// ---- 2. the raw SO6 file ------------------------------------------------------------------------------

struct RawPoint {
  double t, lat, lon, alt_m;
};

std::string upper(std::string s) {
  for (char& c : s)
    if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
  return s;
}

// The store's callsign of each SO6 flight → its distinct-time points in time order (the first row of a
// time wins). A callsign that several flight ids share is stored as "CALLSIGN/FLIGHT_ID".
const std::map<std::string, std::vector<RawPoint>>& raw_flights() {
  static const std::map<std::string, std::vector<RawPoint>> flights = [] {
    std::map<std::string, std::map<double, RawPoint>> by_id;
    std::map<std::string, std::string> callsign_of;
    std::map<std::string, std::set<std::string>> ids_of;
    for (const auto& s : test::read_so6_segments(so6_path(), kDay)) {
      callsign_of.emplace(s.flight_id, s.callsign);
      ids_of[s.callsign].insert(s.flight_id);
      by_id[s.flight_id].try_emplace(s.t_begin, RawPoint{s.t_begin, s.lat_begin, s.lon_begin, s.alt_begin_m});
      by_id[s.flight_id].try_emplace(s.t_end, RawPoint{s.t_end, s.lat_end, s.lon_end, s.alt_end_m});
    }
    std::map<std::string, std::vector<RawPoint>> out;
    for (auto& [fid, pts] : by_id) {
      const std::string& cs = callsign_of[fid];
      const std::string name = upper(ids_of[cs].size() > 1 ? cs + "/" + fid : cs);
      auto& v = out[name];
      for (auto& [t, p] : pts) v.push_back(p);
    }
    return out;
  }();
  return flights;
}

TEST_F(PositionsEurope, EqualToTheRawFileAtSeveralInstants) {
  ASSERT_EQ(raw_flights().size(), 11043u);
  for (const std::string prefix : {"", "RYR", "DLH"})
    for (const double t : instants()) {
      SCOPED_TRACE("callsign '" + prefix + "' at t = " + std::to_string(t));
      // callsign → (lat, lon, alt) of every raw flight present at t, by a plain scan of its points.
      std::map<std::string, RawPoint> want;
      for (const auto& [name, pts] : raw_flights()) {
        if (name.rfind(prefix, 0) != 0) continue;
        for (std::size_t i = 0; i < pts.size(); ++i) {
          if (pts[i].t == t) {
            want[name] = pts[i];
            break;
          }
          if (i + 1 < pts.size() && pts[i].t < t && t < pts[i + 1].t) {
            const double w = (t - pts[i].t) / (pts[i + 1].t - pts[i].t);
            want[name] = {t, (1 - w) * pts[i].lat + w * pts[i + 1].lat,
                          (1 - w) * pts[i].lon + w * pts[i + 1].lon,
                          (1 - w) * pts[i].alt_m + w * pts[i + 1].alt_m};
            break;
          }
        }
      }
      const Positions got =
          positions_at(europe(), t, prefix.empty() ? Query{} : parse_query({{"callsign", prefix}}), kCap);
      ASSERT_EQ(got.positions.size(), want.size());
      if (t > kDay && prefix.empty()) EXPECT_GT(want.size(), 100u);
      for (const Position& p : got.positions) {
        const auto it = want.find(p.callsign);
        ASSERT_NE(it, want.end()) << p.callsign << " is not in the air in the file";
        EXPECT_NEAR(p.lat, it->second.lat, 1e-5) << p.callsign;
        EXPECT_NEAR(p.lon, it->second.lon, 1e-5) << p.callsign;
        EXPECT_NEAR(p.alt_m, it->second.alt_m, 2e-3) << p.callsign;
      }
    }
}

// Scrubbing: every 15 minutes of the day, the whole of Europe at once; the day is busy enough that the
// instants hold more than ten thousand positions in all.
TEST_F(PositionsEurope, ScrubbingTheDayFindsTraffic) {
  std::size_t total = 0;
  for (int k = 0; k < 96; ++k)
    total += positions_at(europe(), kDay + k * 900.0, Query{}, kCap).positions.size();
  EXPECT_GT(total, 10000u);
}

}  // namespace
}  // namespace trailscope
