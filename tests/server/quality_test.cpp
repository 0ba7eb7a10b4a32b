// Data quality on the real Europe SO6 day: the ingest report's and the window summary's counts of
// implausible ground speeds (> 800 kt), altitudes (> FL600) and position jumps (> 800 kt implied) against
// counts made here by plain loops over the ingested points (the jump distance as the chord of unit
// vectors, not the haversine the library uses); the flights split between legs and at teleports by default
// against the rule applied here to the unsplit flights, and AFR116 against the raw file; the summary's CSV
// tables; the upload option's refusal; the rule on small made-up reports (jitter, a spike, a teleport).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <array>
#include <limits>
#include <map>
#include <numbers>

#include "europe_dataset.hpp"
#include "route_fixture.hpp"
#include "so6_segments.hpp"
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

// The splitting rule as documented (trails/quality.hpp), written out over one flight's points: the indices
// where a new flight starts, and whether each is between two legs (true) or at a teleport (false).
constexpr double kSplitSpeed = 1600 * 1852.0 / 3600, kSplitDistance = 50e3, kLegGap = 20 * 3600.0;
std::vector<std::pair<std::size_t, bool>> rule_splits(const PointColumns& p, std::size_t b, std::size_t e) {
  auto first = [&](std::size_t i) {  // time of the first report of point i's position
    while (i > b && p.lat[i - 1] == p.lat[i] && p.lon[i - 1] == p.lon[i]) --i;
    return p.t[i];
  };
  auto impossible = [&](std::size_t x, std::size_t y) {
    const double d = chord_distance(p.lat[x], p.lon[x], p.lat[y], p.lon[y]);
    return d >= kSplitDistance && d / std::max(p.t[y] - first(x), 1.0) > kSplitSpeed;
  };
  std::vector<std::pair<std::size_t, bool>> out;
  std::size_t start = b;  // first point of the piece being built
  for (std::size_t i = b + 1; i < e; ++i) {
    const std::size_t before = out.size();
    if (p.t[i] - p.t[i - 1] > kLegGap) {
      // Two legs of at least two points each.
      if (i - start >= 2 && i + 1 < e && p.t[i + 1] - p.t[i] <= kLegGap) out.push_back({i, true});
    } else if (i >= b + 2 && i + 1 < e && impossible(i - 1, i) && impossible(i - 1, i + 1) &&
               impossible(i - 2, i) && !impossible(i, i + 1) && !impossible(i - 2, i - 1)) {
      out.push_back({i, false});
    }
    if (out.size() != before) start = i;
  }
  return out;
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
      // The first report of the previous sample's position (stale repeats count from there).
      std::size_t first = i > f.begin ? i - 1 : i;
      while (first > f.begin && p.lat[first - 1] == p.lat[i - 1] && p.lon[first - 1] == p.lon[i - 1]) --first;
      if (!(p.t[i] >= t0 && p.t[i] < t1)) continue;
      if (p.speed[i] > kSpeedLimit) ++c.speed, c.max_speed = std::max<double>(c.max_speed, p.speed[i]);
      if (p.alt[i] > kAltLimit) ++c.alt, c.max_alt = std::max<double>(c.max_alt, p.alt[i]);
      if (i > f.begin && p.t[i - 1] >= t0) {
        const double v = chord_distance(p.lat[i - 1], p.lon[i - 1], p.lat[i], p.lon[i]) /
                         std::max(p.t[i] - p.t[first], 1.0);
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
  // The day as ingested by default (split between legs and at teleports), and kept whole on request.
  static const TrailSet& split(ingest::IngestReport* report) { return *test_routes::europe_trails(report); }
  static const TrailSet& unsplit(ingest::IngestReport* report) {
    static ingest::IngestReport rep;
    static const TrailSet set = [] {
      ingest::IngestOptions opts;
      opts.split_jumps = false;
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
  EXPECT_EQ(j["leg_splits"]["count"], 0);
  EXPECT_EQ(whole.leg_splits.count, 0u);
}

// By default the day is split where the rule, applied here to the unsplit flights, says: the same points,
// one more flight per split, the jumps at the splits gone and the one-point spikes still flagged.
TEST_F(QualityEurope, DefaultSplitsEqualTheRuleOverTheUnsplitDay) {
  ingest::IngestReport whole, split;
  const TrailSet& u = unsplit(&whole);
  const TrailSet& s = this->split(&split);
  std::size_t legs = 0, teleports = 0;
  double max_teleport = 0, max_gap = 0;
  for (const Flight& f : u.flights())
    for (const auto& [i, leg] : rule_splits(u.points(), f.begin, f.end)) {
      const auto& p = u.points();
      if (leg) {
        ++legs, max_gap = std::max(max_gap, p.t[i] - p.t[i - 1]);
      } else {
        ++teleports;
        std::size_t k = i - 1;
        while (k > f.begin && p.lat[k - 1] == p.lat[k] && p.lon[k - 1] == p.lon[k]) --k;
        max_teleport = std::max(max_teleport, chord_distance(p.lat[i - 1], p.lon[i - 1], p.lat[i], p.lon[i]) /
                                                  std::max(p.t[i] - p.t[k], 1.0));
      }
    }
  // Measured on the day: 46 pairs of legs (AFR116's among them) and 11 teleports; most of the 2,358
  // jumps are one-point spikes, which stay.
  EXPECT_GT(legs, 10u);
  EXPECT_GT(teleports, 0u);
  EXPECT_EQ(split.leg_splits.count, legs);
  EXPECT_EQ(split.jump_splits.count, teleports);
  EXPECT_EQ(s.num_flights(), u.num_flights() + legs + teleports);
  EXPECT_EQ(split.flights, s.num_flights());
  EXPECT_EQ(s.num_points(), u.num_points());
  for (const Flight& f : s.flights())
    ASSERT_GE(f.end - f.begin, 2u) << f.callsign << ": a split never leaves one point";
  const Counts cs = count(s, -INFINITY, INFINITY), cu = count(u, -INFINITY, INFINITY);
  EXPECT_EQ(split.quality.jumps.count, cs.jumps);
  EXPECT_EQ(cs.jumps, cu.jumps - teleports);  // every teleport was also a flagged jump
  EXPECT_GT(cs.jumps, 1000u);
  EXPECT_EQ(split.quality.speed.count, cu.speed);
  // Each listed split names the flight that starts there.
  ASSERT_FALSE(split.jump_splits.examples.empty());
  ASSERT_FALSE(split.leg_splits.examples.empty());
  for (const auto* list : {&split.jump_splits.examples, &split.leg_splits.examples})
    for (const auto& e : *list) {
      const Flight& f = s.flights()[e.flight_id];
      EXPECT_EQ(f.t_min, e.t);
      EXPECT_EQ(f.callsign, e.callsign);
    }
  for (const auto& e : split.jump_splits.examples) EXPECT_GT(e.value, kSplitSpeed);
  for (const auto& e : split.leg_splits.examples) EXPECT_GT(e.value, kLegGap);
  EXPECT_NEAR(split.jump_splits.examples[0].value, max_teleport, 1e-6 * max_teleport);
  EXPECT_DOUBLE_EQ(split.leg_splits.examples[0].value, max_gap);
  const auto j = split.to_json()["quality"];
  EXPECT_EQ(j["leg_splits"]["count"], legs);
  EXPECT_DOUBLE_EQ(j["leg_splits"]["examples"][0]["value_h"].get<double>(), max_gap / 3600);
}

// AFR116 (flight id 5870046) is two legs under one id: the 2017-12-31 departure still flying at 00:00-01:49
// and the next departure from Paris at 22:58. Its two flights are the raw file's points before and after
// the longest gap, read here from the text.
TEST_F(QualityEurope, Afr116IsSplitIntoItsTwoLegs) {
  std::map<double, std::pair<double, double>> raw;  // t → (lat, lon), first of equal times kept
  for (const auto& seg : test::read_so6_segments(test_routes::europe_so6(), kT0))
    if (seg.flight_id == "5870046") {
      raw.try_emplace(seg.t_begin, seg.lat_begin, seg.lon_begin);
      raw.try_emplace(seg.t_end, seg.lat_end, seg.lon_end);
    }
  ASSERT_GT(raw.size(), 4u);
  double gap = 0, gap_end = 0;
  for (auto it = std::next(raw.begin()); it != raw.end(); ++it)
    if (it->first - std::prev(it)->first > gap) gap = it->first - std::prev(it)->first, gap_end = it->first;
  EXPECT_GT(gap, 20 * 3600.0);  // 01:49:40 → 22:58:00
  const std::size_t first_leg = std::distance(raw.begin(), raw.find(gap_end));
  ingest::IngestReport rep;
  const TrailSet& s = split(&rep);
  std::vector<const Flight*> afr;
  for (const Flight& f : s.flights())
    if (f.callsign == "AFR116") afr.push_back(&f);
  ASSERT_EQ(afr.size(), 2u);
  EXPECT_EQ(afr[0]->t_min, raw.begin()->first);
  EXPECT_EQ(afr[0]->t_max, std::prev(raw.find(gap_end))->first);
  EXPECT_EQ(afr[0]->end - afr[0]->begin, first_leg);
  EXPECT_EQ(afr[1]->t_min, gap_end);
  EXPECT_EQ(afr[1]->t_max, raw.rbegin()->first);
  EXPECT_EQ(afr[1]->end - afr[1]->begin, raw.size() - first_leg);
  EXPECT_FLOAT_EQ(s.points().lat[afr[1]->begin], float(raw.at(gap_end).first));
  // Kept whole on request.
  ingest::IngestReport whole;
  std::size_t n = 0;
  for (const Flight& f : unsplit(&whole).flights()) n += f.callsign == "AFR116";
  EXPECT_EQ(n, 1u);
}

TEST_F(QualityEurope, SummaryFlagsTheWindow) {
  open(test_routes::europe_dataset("whole"));  // as ingested by default: split
  ingest::IngestReport whole;
  const TrailSet& u = split(&whole);
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
  // The same day kept whole: the teleports in the window are jumps again, the same speeds.
  ingest::IngestReport rep;
  auto ds = test_routes::europe_dataset("kept");
  ds->trails = std::make_shared<const TrailSet>(unsplit(&rep));
  store->put(ds);
  const auto j =
      body(get("/api/v1/datasets/kept/summary", {{"t0", std::to_string(t0)}, {"t1", std::to_string(t1)}}));
  const Counts ck = count(*ds->trails, t0, t1);
  EXPECT_EQ(j["quality"]["jumps"]["count"], ck.jumps);
  EXPECT_GE(ck.jumps, cu.jumps);
  EXPECT_EQ(j["quality"]["speed"]["count"], ck.speed);
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

// A position report jumping 10° in 10 s and staying there is split by default; asked not to, it stays one
// flight with the jump reported.
TEST(QualityIngest, PositionReportsSplitAtTeleportsByDefault) {
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
  ingest::IngestOptions off;
  off.split_jumps = false;
  const TrailSet b = ingest::ingest_file(csv.string(), off, &kept);
  EXPECT_EQ(b.num_flights(), 1u);
  EXPECT_EQ(kept.jump_splits.count, 0u);
  EXPECT_EQ(kept.quality.jumps.count, 1u);
}

// What the rule leaves whole: 1 km of jitter between samples 1 s apart (3,600 kt, but under 50 km), a
// one-point spike 500 km out and back, a jump at the last sample (unconfirmed); and what it splits: two
// legs 21 h apart in the same place.
TEST(QualityIngest, JitterSpikesAndUnconfirmedJumpsStayWhole) {
  auto build = [](const std::vector<std::array<double, 3>>& pts, TrailSetBuilder::Stats* st) {
    TrailSetBuilder b;
    for (const auto& [t, lat, lon] : pts) {
      Sample s;
      s.t = t, s.lat = float(lat), s.lon = float(lon);
      b.add("abc123", "X", s);
    }
    return b.build(st, std::numeric_limits<double>::infinity(), true);
  };
  TrailSetBuilder::Stats st;
  std::vector<std::array<double, 3>> jitter;
  for (int i = 0; i < 20; ++i) jitter.push_back({kT0 + i, 50.0 + (i % 2) * 0.009, 8.0});
  EXPECT_EQ(build(jitter, &st).num_flights(), 1u);
  EXPECT_EQ(st.jump_splits, 0u);
  const std::vector<std::array<double, 3>> spike = {
      {kT0, 50, 8}, {kT0 + 10, 50.01, 8}, {kT0 + 20, 54.5, 8}, {kT0 + 30, 50.03, 8}, {kT0 + 40, 50.04, 8}};
  EXPECT_EQ(build(spike, &st).num_flights(), 1u);
  const std::vector<std::array<double, 3>> last = {{kT0, 50, 8}, {kT0 + 10, 50.01, 8}, {kT0 + 20, 55, 8}};
  EXPECT_EQ(build(last, &st).num_flights(), 1u);
  const std::vector<std::array<double, 3>> legs = {
      {kT0, 50, 8}, {kT0 + 10, 50.01, 8}, {kT0 + 21 * 3600, 50.01, 8}, {kT0 + 21 * 3600 + 10, 50.02, 8}};
  EXPECT_EQ(build(legs, &st).num_flights(), 2u);
  EXPECT_EQ(st.leg_splits, 1u);
  EXPECT_EQ(st.jump_splits, 0u);
  // The teleport of the test above, with the builder alone.
  const std::vector<std::array<double, 3>> tele = {
      {kT0, 50, 8}, {kT0 + 10, 50.01, 8}, {kT0 + 20, 60, 8}, {kT0 + 30, 60.01, 8}};
  EXPECT_EQ(build(tele, &st).num_flights(), 2u);
  EXPECT_EQ(st.jump_splits, 1u);
}

}  // namespace
}  // namespace trailscope::server
