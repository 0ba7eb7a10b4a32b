// Data quality on the real Europe SO6 day: the ingest report's and the window summary's counts of
// implausible ground speeds (> 800 kt), altitudes (> FL600) and position jumps (> 800 kt implied) against
// counts made here by plain loops over the ingested points (the jump distance as the chord of unit
// vectors, not the haversine the library uses); the flights split at jumps on request (SO6 keeps them
// whole by default); the summary's CSV tables; the upload option's refusal.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>

#include "europe_dataset.hpp"
#include "route_fixture.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::server {
namespace {

constexpr double kT0 = 1514764800.0;                 // 2018-01-01T00:00:00Z
constexpr double kSpeedLimit = 800 * 1852.0 / 3600;  // 800 kt in m/s, as documented
constexpr double kAltLimit = 60000 * 0.3048;         // FL600 in metres

// Great-circle distance from the chord between unit vectors (a formula other than the haversine).
double chord_distance(double lat1, double lon1, double lat2, double lon2) {
  const double r = std::numbers::pi / 180;
  const double x1 = std::cos(lat1 * r) * std::cos(lon1 * r), y1 = std::cos(lat1 * r) * std::sin(lon1 * r),
               z1 = std::sin(lat1 * r);
  const double x2 = std::cos(lat2 * r) * std::cos(lon2 * r), y2 = std::cos(lat2 * r) * std::sin(lon2 * r),
               z2 = std::sin(lat2 * r);
  const double chord = std::sqrt((x1 - x2) * (x1 - x2) + (y1 - y2) * (y1 - y2) + (z1 - z2) * (z1 - z2));
  return 2 * 6371008.8 * std::asin(std::min(1.0, chord / 2));
}

struct Counts {
  std::uint64_t speed = 0, alt = 0, jumps = 0;
  double max_speed = 0, max_alt = 0, max_jump = 0;
};
// Over the points with t in [t0, t1) (a jump when both of its samples are).
Counts count(const TrailSet& set, double t0, double t1) {
  Counts c;
  const auto& p = set.points();
  for (const Flight& f : set.flights())
    for (std::size_t i = f.begin; i < f.end; ++i) {
      if (!(p.t[i] >= t0 && p.t[i] < t1)) continue;
      if (p.speed[i] > kSpeedLimit) ++c.speed, c.max_speed = std::max<double>(c.max_speed, p.speed[i]);
      if (p.alt[i] > kAltLimit) ++c.alt, c.max_alt = std::max<double>(c.max_alt, p.alt[i]);
      if (i > f.begin && p.t[i - 1] >= t0) {
        const double v = chord_distance(p.lat[i - 1], p.lon[i - 1], p.lat[i], p.lon[i]) /
                         std::max(p.t[i] - p.t[i - 1], 1.0);
        if (v > kSpeedLimit) ++c.jumps, c.max_jump = std::max(c.max_jump, v);
      }
    }
  return c;
}

class QualityEurope : public test_routes::RouteFixture {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(test_routes::europe_so6())) GTEST_SKIP() << "the Europe SO6 day is absent";
  }
  // SO6 keeps its flights whole by default; the same day split at its jumps, on request.
  static const TrailSet& unsplit(ingest::IngestReport* report) { return *test_routes::europe_trails(report); }
  static const TrailSet& split(ingest::IngestReport* report) {
    static ingest::IngestReport rep;
    static const TrailSet set = [] {
      ingest::IngestOptions opts;
      opts.split_jumps = true;
      return ingest::ingest_file(test_routes::europe_so6().string(), opts, &rep);
    }();
    *report = rep;
    return set;
  }
};

TEST_F(QualityEurope, IngestReportCountsEqualPlainLoops) {
  ingest::IngestReport whole;
  const TrailSet& u = unsplit(&whole);
  const Counts c = count(u, -INFINITY, INFINITY);
  // The day has all three kinds.
  EXPECT_GT(c.speed, 100u);
  EXPECT_GT(c.alt, 0u);
  EXPECT_GT(c.jumps, 100u);
  EXPECT_EQ(whole.quality.speed.count, c.speed);
  EXPECT_EQ(whole.quality.altitude.count, c.alt);
  EXPECT_EQ(whole.quality.jumps.count, c.jumps);
  EXPECT_EQ(whole.jump_splits.count, 0u);
  ASSERT_EQ(whole.quality.speed.examples.size(), 10u);
  EXPECT_FLOAT_EQ(whole.quality.speed.examples[0].value, c.max_speed);
  EXPECT_FLOAT_EQ(whole.quality.altitude.examples[0].value, c.max_alt);
  EXPECT_NEAR(whole.quality.jumps.examples[0].value, c.max_jump, 1e-6 * c.max_jump);
  for (const auto& e : whole.quality.speed.examples) {
    EXPECT_GT(e.value, kSpeedLimit);
    EXPECT_EQ(e.callsign, u.flights()[e.flight_id].callsign);
  }
  // The JSON of the report: the limits in knots and flight levels.
  const auto j = whole.to_json()["quality"];
  EXPECT_DOUBLE_EQ(j["limits"]["speed_kt"].get<double>(), 800);
  EXPECT_DOUBLE_EQ(j["limits"]["altitude_fl"].get<double>(), 600);
  EXPECT_EQ(j["speed"]["count"], c.speed);
  EXPECT_EQ(j["jump_splits"]["count"], 0);

  // Asked to, every jump splits its flight once: the same points, c.jumps more flights, no jump left.
  ingest::IngestReport split_report;
  const TrailSet& s = split(&split_report);
  auto& split = split_report;
  EXPECT_EQ(split.jump_splits.count, c.jumps);
  EXPECT_EQ(s.num_flights(), u.num_flights() + c.jumps);
  EXPECT_EQ(s.num_points(), u.num_points());
  EXPECT_EQ(split.quality.jumps.count, 0u);
  EXPECT_EQ(count(s, -INFINITY, INFINITY).jumps, 0u);
  EXPECT_EQ(split.quality.speed.count, c.speed);
  EXPECT_EQ(split.quality.altitude.count, c.alt);
  // Each listed split names the flight that starts at the jump.
  ASSERT_FALSE(split.jump_splits.examples.empty());
  for (const auto& e : split.jump_splits.examples) {
    const Flight& f = s.flights()[e.flight_id];
    EXPECT_EQ(f.t_min, e.t);
    EXPECT_EQ(f.callsign, e.callsign);
    EXPECT_GT(e.value, kSpeedLimit);
  }
  EXPECT_NEAR(split.jump_splits.examples[0].value, c.max_jump, 1e-6 * c.max_jump);
}

TEST_F(QualityEurope, SummaryFlagsTheWindow) {
  open(test_routes::europe_dataset("whole"));
  ingest::IngestReport whole;
  const TrailSet& u = unsplit(&whole);
  const double t0 = kT0 + 6 * 3600, t1 = kT0 + 12 * 3600;
  const Counts cu = count(u, t0, t1);
  EXPECT_GT(cu.speed, 10u);
  EXPECT_GT(cu.jumps, 10u);
  const auto w =
      body(get("/api/v1/datasets/whole/summary", {{"t0", std::to_string(t0)}, {"t1", std::to_string(t1)}}));
  EXPECT_EQ(w["quality"]["speed"]["count"], cu.speed);
  EXPECT_EQ(w["quality"]["altitude"]["count"], cu.alt);
  EXPECT_EQ(w["quality"]["jumps"]["count"], cu.jumps);
  EXPECT_FLOAT_EQ(w["quality"]["speed"]["examples"][0]["value"].get<float>(), float(cu.max_speed));
  // The same day split at its jumps: no jump left, the same speeds.
  ingest::IngestReport rep;
  auto ds = test_routes::europe_dataset("split");
  ds->trails = std::make_shared<const TrailSet>(split(&rep));
  store->put(ds);
  const auto j =
      body(get("/api/v1/datasets/split/summary", {{"t0", std::to_string(t0)}, {"t1", std::to_string(t1)}}));
  EXPECT_EQ(j["quality"]["jumps"]["count"], 0);
  EXPECT_EQ(j["quality"]["speed"]["count"], count(*ds->trails, t0, t1).speed);
  // The CSV tables: the counts in totals, the examples in quality.
  const Response totals = get("/api/v1/datasets/whole/summary",
                              {{"t0", std::to_string(t0)}, {"t1", std::to_string(t1)}, {"format", "csv"}});
  EXPECT_NE(totals.body.find("\nimplausible_speeds," + std::to_string(cu.speed) + "\n"), std::string::npos)
      << totals.body;
  EXPECT_NE(totals.body.find("\nimplausible_altitudes," + std::to_string(cu.alt) + "\n"), std::string::npos);
  EXPECT_NE(totals.body.find("\nposition_jumps," + std::to_string(cu.jumps) + "\n"), std::string::npos);
  const Response ex =
      get("/api/v1/datasets/whole/summary",
          {{"t0", std::to_string(t0)}, {"t1", std::to_string(t1)}, {"format", "csv"}, {"table", "quality"}});
  ASSERT_EQ(ex.status, 200) << ex.body;
  EXPECT_EQ(ex.body.substr(0, ex.body.find('\n')), "kind,flight_id,callsign,t,value");
  std::size_t rows = 0;
  for (char ch : ex.body) rows += ch == '\n';
  EXPECT_EQ(rows - 1, w["quality"]["speed"]["examples"].size() + w["quality"]["altitude"]["examples"].size() +
                          w["quality"]["jumps"]["examples"].size());
}

class QualityUpload : public test_routes::RouteFixture {
 protected:
  QualityUpload() {
    TrailSetBuilder b;
    Sample s;
    s.t = kT0, s.lat = 50, s.lon = 8;
    b.add("abc123", "ONE", s);
    auto ds = std::make_shared<Dataset>();
    ds->id = "one", ds->name = "one", ds->format = "test", ds->created = "2026-01-01T00:00:00Z";
    ds->trails = std::make_shared<const TrailSet>(b.build());
    open(ds);
  }
};

TEST_F(QualityUpload, SplitJumpsOptionRefusal) {
  const Response r = send("POST", "/api/v1/datasets", "x", {{"name", "new"}, {"split_jumps", "yes"}});
  expect_error(r, 400, "invalid_argument", "split_jumps");
  EXPECT_EQ(body(r)["detail"], "split_jumps must be 'true' or 'false', got 'yes'");
}

// A position report jumping 10° in 10 s is split by default; asked not to, it stays one flight with the
// jump reported.
TEST(QualityIngest, PositionReportsSplitAtJumpsByDefault) {
  test::TempDir tmp;
  const auto csv = tmp.path() / "jump.csv";
  {
    std::ofstream f(csv);
    f << "time,icao24,lat,lon,velocity,heading,vertrate,callsign,onground,alert,spi,squawk,baroaltitude,"
         "geoaltitude,lastposupdate,lastcontact\n";
    for (int i = 0; i < 6; ++i)
      f << 1514764800 + 10 * i << ",abc123," << (i < 3 ? 50.0 + 0.01 * i : 60.0 + 0.01 * i)
        << ",8.0,200,0,0,JMP1,false,false,false,1000,10000,10000,0,0\n";
  }
  ingest::IngestReport split, kept;
  const TrailSet a = ingest::ingest_file(csv.string(), {}, &split);
  EXPECT_EQ(a.num_flights(), 2u);
  EXPECT_EQ(split.jump_splits.count, 1u);
  ASSERT_EQ(split.jump_splits.examples.size(), 1u);
  EXPECT_EQ(split.jump_splits.examples[0].t, 1514764830);
  EXPECT_EQ(split.jump_splits.examples[0].flight_id, 1u);
  // ~10° of latitude in 10 s, by the chord formula here.
  const double d = chord_distance(50.02, 8, 60.03, 8);
  EXPECT_NEAR(split.jump_splits.examples[0].value, d / 10, 1e-6 * d);
  ingest::IngestOptions opts;
  opts.split_jumps = false;
  const TrailSet b = ingest::ingest_file(csv.string(), opts, &kept);
  EXPECT_EQ(b.num_flights(), 1u);
  EXPECT_EQ(kept.jump_splits.count, 0u);
  EXPECT_EQ(kept.quality.jumps.count, 1u);
}

}  // namespace
}  // namespace trailscope::server
