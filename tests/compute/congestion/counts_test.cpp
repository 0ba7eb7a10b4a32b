// Congestion counts on small synthetic flights whose answers are worked out by hand in the comments:
// a corner cut and a corner touched between two samples, a sector crossed between two samples (which
// method=samples misses), a climb through a sector's floor, entries and re-entries, hotspot runs, the PRU
// complexity of three aircraft, the grid, the antimeridian, and the request checks. Coordinates are
// exact in float (the TrailSet stores float degrees), so the crossing times below are exact too.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <string>

#include "trailscope/congestion/counts.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::congestion {
namespace {

constexpr float kNaNf = std::numeric_limits<float>::quiet_NaN();
// Flights are not split at long gaps here (the builder splits above 30 min by default).
constexpr double kNoSplit = std::numeric_limits<double>::infinity();

Sample sample(double t, float lon, float lat, float alt_m) {
  Sample s;
  s.t = t, s.lat = lat, s.lon = lon, s.alt = alt_m;
  return s;
}
float fl(double level) {
  return static_cast<float>(level * 100 * 0.3048);
}

// One square sector [w, e] x [s, n] between two flight levels, through parse_sectors.
std::vector<Sector> square(double w, double s, double e, double n, int lower_fl = 100, int upper_fl = 200,
                           std::optional<double> peak = std::nullopt,
                           std::optional<double> sustained = std::nullopt) {
  nlohmann::json props = {{"name", "SQ"}, {"lower_fl", lower_fl}, {"upper_fl", upper_fl}};
  if (peak) props["peak"] = *peak;
  if (sustained) props["sustained"] = *sustained;
  const nlohmann::json doc = {
      {"type", "FeatureCollection"},
      {"features",
       {{{"type", "Feature"},
         {"properties", props},
         {"geometry", {{"type", "Polygon"}, {"coordinates", {{{w, s}, {e, s}, {e, n}, {w, n}, {w, s}}}}}}}}}};
  return parse_sectors(doc);
}

CountsRequest request(double t0, double t1, std::vector<Sector> sectors, Method m = Method::interpolated) {
  CountsRequest r;
  r.query.t0 = t0, r.query.t1 = t1;
  r.sectors = std::move(sectors);
  r.method = m;
  return r;
}

std::vector<std::uint32_t> periods_with(const Series& s, std::uint32_t value) {
  std::vector<std::uint32_t> out;
  for (std::size_t i = 0; i < s.index.size(); ++i)
    if (s.value[i] == value) out.push_back(s.index[i]);
  return out;
}

using V = std::vector<std::uint32_t>;

// lon = -0.25 + 0.75u, lat = 0.5 + 0.75u over t = 750u: both samples are outside the unit square, the
// path cuts its north-west corner for u in [1/3, 2/3], i.e. t in [250, 500]. Periods of 60 s meeting it:
// k = 4 ([240, 300)) to 8 ([480, 540)).
TEST(CongestionCounts, CornerCutBetweenSamplesCounts) {
  TrailSetBuilder b;
  b.add("aaaaaa", "CUT", sample(0, -0.25f, 0.5f, fl(150)));
  b.add("aaaaaa", "CUT", sample(750, 0.5f, 1.25f, fl(150)));
  const TrailSet set = b.build(nullptr, kNoSplit);
  const auto r = count(set, request(0, 900, square(0, 0, 1, 1)));
  ASSERT_EQ(r.volumes.size(), 1u);
  EXPECT_EQ(r.volumes[0].occupancy.index, (V{4, 5, 6, 7, 8}));
  EXPECT_EQ(periods_with(r.volumes[0].occupancy, 1), (V{4, 5, 6, 7, 8}));
  EXPECT_EQ(r.volumes[0].entries.index, (V{0}));  // one entry, at t = 250, in the window [0, 900)
  EXPECT_EQ(r.volumes[0].entries.value, (V{1}));
  const auto s = count(set, request(0, 900, square(0, 0, 1, 1), Method::samples));
  EXPECT_TRUE(s.volumes[0].occupancy.index.empty());
  EXPECT_TRUE(s.volumes[0].entries.index.empty());
}

// lon = -1 + 2u, lat = 2u over t = 600u passes exactly through the corner (0, 1) at t = 300 and is
// outside before and after: inside for that one instant, which lies in period 5 ([300, 360)) only.
TEST(CongestionCounts, CornerTouchedAtOneInstantCounts) {
  TrailSetBuilder b;
  b.add("aaaaaa", "TOUCH", sample(0, -1, 0, fl(150)));
  b.add("aaaaaa", "TOUCH", sample(600, 1, 2, fl(150)));
  const TrailSet set = b.build(nullptr, kNoSplit);
  const auto r = count(set, request(0, 900, square(0, 0, 1, 1)));
  EXPECT_EQ(r.volumes[0].occupancy.index, (V{5}));
  EXPECT_EQ(r.volumes[0].occupancy.value, (V{1}));
  EXPECT_EQ(r.volumes[0].entries.value, (V{1}));
  // Shifted by 1e-3° to the east the path misses the corner altogether.
  TrailSetBuilder b2;
  b2.add("aaaaaa", "MISS", sample(0, -1, 0 + 0.0009765625f, fl(150)));
  b2.add("aaaaaa", "MISS", sample(600, 1, 2 + 0.0009765625f, fl(150)));
  const auto m = count(b2.build(nullptr, kNoSplit), request(0, 900, square(0, 0, 1, 1)));
  EXPECT_TRUE(m.volumes[0].occupancy.index.empty());
}

// A small sector [0, 0.125]² crossed at lat 0.0625 between samples 2° apart: inside for
// u in [0.5, 0.5625] of t = 1200u, i.e. t in [600, 675], periods 10 and 11. The samples (t = 0, 1200)
// are both outside, so method=samples sees nothing; a third sample inside at t = 630 makes it see
// period 10 only (the sample's time lies in [600, 660) alone).
TEST(CongestionCounts, VolumeCrossedBetweenSamplesSamplesMissIt) {
  const auto sq = square(0, 0, 0.125, 0.125);
  TrailSetBuilder b;
  b.add("aaaaaa", "CROSS", sample(0, -1, 0.0625f, fl(150)));
  b.add("aaaaaa", "CROSS", sample(1200, 1, 0.0625f, fl(150)));
  const TrailSet set = b.build(nullptr, kNoSplit);
  const auto r = count(set, request(0, 1800, sq));
  EXPECT_EQ(r.volumes[0].occupancy.index, (V{10, 11}));
  const auto s = count(set, request(0, 1800, sq, Method::samples));
  EXPECT_TRUE(s.volumes[0].occupancy.index.empty());

  TrailSetBuilder b2;
  b2.add("aaaaaa", "CROSS", sample(0, -1, 0.0625f, fl(150)));
  b2.add("aaaaaa", "CROSS", sample(630, 0.0625f, 0.0625f, fl(150)));
  b2.add("aaaaaa", "CROSS", sample(1200, 1, 0.0625f, fl(150)));
  const TrailSet set2 = b2.build(nullptr, kNoSplit);
  const auto s2 = count(set2, request(0, 1800, sq, Method::samples));
  EXPECT_EQ(s2.volumes[0].occupancy.index, (V{10}));
  EXPECT_EQ(s2.volumes[0].entries.value, (V{1}));
}

// Straight up through the floor: FL50 at t = 0 to FL150 at t = 1000 inside the polygon; the floor FL100
// is reached at t = 500 exactly, so periods 8 ([480, 540)) to 16 ([960, 1020)) with 60-s steps.
TEST(CongestionCounts, ClimbThroughTheFloor) {
  TrailSetBuilder b;
  b.add("aaaaaa", "CLIMB", sample(0, 0.5f, 0.5f, fl(50)));
  b.add("aaaaaa", "CLIMB", sample(1000, 0.5f, 0.5f, fl(150)));
  const auto r = count(b.build(nullptr, kNoSplit), request(0, 1200, square(0, 0, 1, 1)));
  EXPECT_EQ(r.volumes[0].occupancy.index, (V{8, 9, 10, 11, 12, 13, 14, 15, 16}));
}

// In at t = 50, out at 150, in again at 250, out at 350: two entries (a re-entry counts again). A second
// flight whose first sample (t = 1000) is inside enters there. Entry windows of 600 s every 300 s:
// [0,600) sees both of the first flight's entries (50, 250), [300,900) none, [600,1200) and [900,1500)
// the second flight's.
TEST(CongestionCounts, EntriesAndReentries) {
  TrailSetBuilder b;
  b.add("aaaaaa", "ZIG", sample(0, -0.5f, 0.5f, fl(150)));
  b.add("aaaaaa", "ZIG", sample(100, 0.5f, 0.5f, fl(150)));
  b.add("aaaaaa", "ZIG", sample(200, 1.5f, 0.5f, fl(150)));
  b.add("aaaaaa", "ZIG", sample(300, 0.5f, 0.5f, fl(150)));
  b.add("aaaaaa", "ZIG", sample(400, -0.5f, 0.5f, fl(150)));
  b.add("bbbbbb", "START", sample(1000, 0.5f, 0.5f, fl(150)));
  b.add("bbbbbb", "START", sample(1100, 0.25f, 0.5f, fl(150)));
  const TrailSet set = b.build(nullptr, kNoSplit);
  auto req = request(0, 1800, square(0, 0, 1, 1));
  req.entry_window_s = 600, req.entry_step_s = 300;
  const auto r = count(set, req);
  EXPECT_EQ(r.entry_windows, 6u);
  EXPECT_EQ(r.volumes[0].entries.dense(6), (V{2, 0, 1, 1, 0, 0}));
  // Occupancy counts the flight once per period even with two stays in it: [50,150] and [250,350]
  // meet periods 0..2 and 4..5.
  EXPECT_EQ(r.volumes[0].occupancy.dense(7), (V{1, 1, 1, 0, 1, 1, 0}));
  // Samples: ZIG is inside at 100 and 300 (entries both, its previous samples are outside), START at
  // 1000 (its first sample) and 1100 (not an entry).
  req.method = Method::samples;
  const auto s = count(set, req);
  EXPECT_EQ(s.volumes[0].entries.dense(6), (V{2, 1, 1, 1, 0, 0}));
}

// Four flights parked inside a sector (one position, several samples): F1 [0, 590], F2 [100, 400],
// F3 [200, 300], F4 [250, 270]. Occupancy per 60-s period: 1 2 2 3 4 3 2 1 1 1 (period 5 is [300, 360):
// F3's last instant 300 is in it). Peak 2.5: the run 3..5, peak 4 at period 4 (t = 240), excess 1.5, all
// four flights. Sustained 1 for 3 periods: the run 1..6 (six periods), peak 4, excess 3; F1-F4 involved.
TEST(CongestionCounts, HotspotRuns) {
  TrailSetBuilder b;
  const auto park = [&](const char* id, const char* cs, double from, double to) {
    for (double t = from; t < to; t += 10) b.add(id, cs, sample(t, 0.5f, 0.5f, fl(150)));
    b.add(id, cs, sample(to, 0.5f, 0.5f, fl(150)));
  };
  park("aaaaa1", "F1", 0, 590);
  park("aaaaa2", "F2", 100, 400);
  park("aaaaa3", "F3", 200, 300);
  park("aaaaa4", "F4", 250, 270);
  const TrailSet set = b.build(nullptr, kNoSplit);
  auto req = request(0, 600, square(0, 0, 1, 1, 100, 200, 2.5, 1.0));
  const auto r = count(set, req);
  EXPECT_EQ(r.volumes[0].occupancy.dense(10), (V{1, 2, 2, 3, 4, 3, 2, 1, 1, 1}));
  ASSERT_EQ(r.hotspots.size(), 2u);
  EXPECT_EQ(r.hotspots_total, 2u);
  // Ordered by excess: the sustained one (3) first.
  const Hotspot& sus = r.hotspots[0];
  EXPECT_EQ(sus.kind, HotspotKind::sustained);
  EXPECT_EQ(sus.first_step, 1u);
  EXPECT_EQ(sus.last_step, 6u);
  EXPECT_EQ(sus.start, 60);
  EXPECT_EQ(sus.end, 420);
  EXPECT_EQ(sus.peak, 4u);
  EXPECT_EQ(sus.peak_time, 240);
  EXPECT_EQ(sus.excess, 3);
  EXPECT_EQ(sus.flights.size(), 4u);
  const Hotspot& pk = r.hotspots[1];
  EXPECT_EQ(pk.kind, HotspotKind::peak);
  EXPECT_EQ(pk.first_step, 3u);
  EXPECT_EQ(pk.last_step, 5u);
  EXPECT_EQ(pk.threshold, 2.5);
  EXPECT_EQ(pk.excess, 1.5);
  ASSERT_EQ(pk.flights.size(), 4u);
  std::set<std::string> names;
  for (const auto& f : pk.flights) names.insert(f.callsign);
  EXPECT_EQ(names, (std::set<std::string>{"F1", "F2", "F3", "F4"}));
  // Seven periods needed: the six-period run is no longer a sustained hotspot. The request's
  // thresholds do not override the sector's.
  req.sustained_steps = 7;
  req.peak = 100;
  const auto r7 = count(set, req);
  ASSERT_EQ(r7.hotspots.size(), 1u);
  EXPECT_EQ(r7.hotspots[0].kind, HotspotKind::peak);
  // Only F1 is counted in the single-flight periods, and a peak of 0.5 over 7..9 lists F1 alone.
  auto req2 = request(0, 600, square(0, 0, 1, 1, 100, 200, 0.5));
  const auto r2 = count(set, req2);
  ASSERT_EQ(r2.hotspots.size(), 1u);  // 0..9 is one run (every period has a flight)
  EXPECT_EQ(r2.hotspots[0].first_step, 0u);
  EXPECT_EQ(r2.hotspots[0].last_step, 9u);
  EXPECT_EQ(r2.hotspots[0].end, 600);
}

// Three aircraft in one sector within one hour, every attribute known:
//   A: east along lat 1 from lon 0.5 (t 0) to 1.5 (t 1800), FL300 level: heading 90°, cruise,
//      60·cos(1°) NM in 0.5 h ≈ 119.98 kt;
//   B: north along lon 1 from lat 0.5 (t 900) to 1.5 (t 2700), FL200 → FL380: heading 0°, 600 ft/min
//      (climbing), 120 kt;
//   C: south along lon 1.25 from lat 1.75 (t 1200) to 0.25 (t 2400), FL300: heading 180°, cruise,
//      90 NM in 1/3 h = 270 kt.
// Overlaps: A-B [900, 1800] 900 s, A-C [1200, 1800] 600 s, B-C [1200, 2400] 1200 s: 2700 s = 0.75 h.
// Horizontal (heading difference > 20°): all three pairs, 0.75 h. Vertical (attitudes differ): A-B and
// B-C, 2100 s. Speed (> 35 kt apart): A-C and B-C, 1800 s. Flight hours 0.5 + 0.5 + 1/3.
TEST(CongestionCounts, ComplexityOfThreeAircraft) {
  TrailSetBuilder b;
  b.add("aaaaaa", "A", sample(0, 0.5f, 1, fl(300)));
  b.add("aaaaaa", "A", sample(1800, 1.5f, 1, fl(300)));
  b.add("bbbbbb", "B", sample(900, 1, 0.5f, fl(200)));
  b.add("bbbbbb", "B", sample(2700, 1, 1.5f, fl(380)));
  b.add("cccccc", "C", sample(1200, 1.25f, 1.75f, fl(300)));
  b.add("cccccc", "C", sample(2400, 1.25f, 0.25f, fl(300)));
  const TrailSet set = b.build(nullptr, kNoSplit);
  const auto r = count(set, request(0, 3600, square(0, 0, 2, 2, 0, 400)));
  ASSERT_EQ(r.complexity.size(), 1u);
  const ComplexityCell& c = r.complexity[0];
  const double fh = 0.5 + 0.5 + 1.0 / 3.0;
  EXPECT_NEAR(c.flight_hours, fh, 1e-12);
  EXPECT_NEAR(c.interaction_hours, 0.75, 1e-12);
  EXPECT_NEAR(c.horizontal_hours, 0.75, 1e-12);
  EXPECT_NEAR(c.vertical_hours, 2100.0 / 3600, 1e-12);
  EXPECT_NEAR(c.speed_hours, 0.5, 1e-12);
  EXPECT_NEAR(c.adjusted_density(), 60 * 0.75 / fh, 1e-9);  // 33.75 min per flight hour
  EXPECT_NEAR(c.structural_index(), (0.75 + 2100.0 / 3600 + 0.5) / 0.75, 1e-9);
  EXPECT_NEAR(c.score(), 60 * 0.75 / fh * (0.75 + 2100.0 / 3600 + 0.5) / 0.75, 1e-9);  // 82.5
  EXPECT_NEAR(c.score(), 82.5, 1e-9);
  // Two windows of an hour split the interactions at t = 1800: A-B and A-C end there.
  const auto r2 = count(set, request(0, 7200, square(0, 0, 2, 2, 0, 400)));
  ASSERT_EQ(r2.complexity.size(), 1u);  // everything ends by 2700 < 3600
  // The speed threshold against the differences: A-C 270 - 119.98 = 150.018 kt, B-C 150 kt.
  auto req = request(0, 3600, square(0, 0, 2, 2, 0, 400));
  req.complexity_params.speed_kt = 150.01;  // A-C only
  EXPECT_NEAR(count(set, req).complexity[0].speed_hours, 600.0 / 3600, 1e-12);
  req.complexity_params.speed_kt = 150.05;  // neither
  EXPECT_NEAR(count(set, req).complexity[0].speed_hours, 0, 1e-12);
  req.complexity_params.speed_kt = 149.99;  // both
  EXPECT_NEAR(count(set, req).complexity[0].speed_hours, 0.5, 1e-12);
}

// The grid: a level flight east along lat 45.1 at FL330 (layer 11: [33000, 36000) ft) from lon 10 to
// lon 11 crosses the columns of row 405 ([45, 45 1/3)), whose width is (1/3°)/cos(45 1/6°). Every
// cell it visits is listed, each with the flight in it during the periods of its stay, and the stays
// tile the flight's time: the sum over cells of stay lengths is the flight's duration.
TEST(CongestionCounts, GridCellsAlongAFlight) {
  TrailSetBuilder b;
  b.add("aaaaaa", "EAST", sample(0, 10, 45.125f, fl(340)));
  b.add("aaaaaa", "EAST", sample(3600, 11, 45.125f, fl(340)));
  const TrailSet set = b.build(nullptr, kNoSplit);
  CountsRequest req;
  req.query.t0 = 0, req.query.t1 = 3600;
  req.query.bbox = BBox{5, 40, 15, 50};
  req.step_s = 60;
  const auto r = count(set, req);
  const double w = grid_column_width(405);
  const int c_first = static_cast<int>(std::floor((10 + 180) / w));
  const int c_last = static_cast<int>(std::floor((11 + 180) / w));
  ASSERT_EQ(r.volumes.size(), static_cast<std::size_t>(c_last - c_first + 1));
  double total_hours = 0;
  for (std::size_t i = 0; i < r.volumes.size(); ++i) {
    EXPECT_EQ(r.volumes[i].id, "r405c" + std::to_string(c_first + static_cast<int>(i)) + "l11");
    // The cell's stay: lon crosses [west, east) at t = 3600·(lon - 10).
    const double a = std::max(0.0, 3600 * (r.volumes[i].bounds.west - 10));
    const double e = std::min(3600.0, 3600 * (r.volumes[i].bounds.east - 10));
    V expect;
    for (std::uint32_t k = 0; k < 60; ++k)
      if (k * 60.0 < e && k * 60.0 + 60 > a) expect.push_back(k);
    EXPECT_EQ(r.volumes[i].occupancy.index, expect) << r.volumes[i].id;
    // One entry, at a (t = 0 for the first cell: the first sample), counted in every entry window
    // [1200j, min(1200j + 3600, 3600)) holding it.
    V windows;
    for (std::uint32_t j = 0; j < 3; ++j)
      if (1200.0 * j <= a && a < 3600) windows.push_back(j);
    EXPECT_EQ(r.volumes[i].entries.index, windows) << r.volumes[i].id;
    total_hours += (e - a) / 3600;
  }
  EXPECT_NEAR(total_hours, 1.0, 1e-12);
  EXPECT_NEAR(r.complexity_total.flight_hours, 1.0, 1e-9);
  EXPECT_EQ(r.complexity_total.interaction_hours, 0);
}

// A flight crossing 180° eastward from 179.5 to -179.5 along lat 0.125 at FL310 (layer 10) crosses 180°
// at t = 300. A sector on each side sees its half. On the grid (columns 1/3° wide at the equator, so
// 1.5 columns a side) it visits columns 1078 and 1079, then 0 and 1 of row 270; lon 180 counts as -180,
// so the last column's stay ends open at 300 and column 0's starts there.
TEST(CongestionCounts, Antimeridian) {
  TrailSetBuilder b;
  b.add("aaaaaa", "DATE", sample(0, 179.5f, 0.125f, fl(310)));
  b.add("aaaaaa", "DATE", sample(600, -179.5f, 0.125f, fl(310)));
  const TrailSet set = b.build(nullptr, kNoSplit);
  nlohmann::json doc = {
      {"type", "FeatureCollection"},
      {"features",
       {{{"type", "Feature"},
         {"properties", {{"name", "EAST"}, {"lower_fl", 0}, {"upper_fl", 400}}},
         {"geometry",
          {{"type", "Polygon"}, {"coordinates", {{{179, 0}, {180, 0}, {180, 1}, {179, 1}, {179, 0}}}}}}},
        {{"type", "Feature"},
         {"properties", {{"name", "WEST"}, {"lower_fl", 0}, {"upper_fl", 400}}},
         {"geometry",
          {{"type", "Polygon"},
           {"coordinates", {{{-180, 0}, {-179, 0}, {-179, 1}, {-180, 1}, {-180, 0}}}}}}}}}};
  const auto r = count(set, request(0, 600, parse_sectors(doc)));
  // EAST: t in [0, 300] (periods 0..5: 300 is in [300, 360)); WEST: [300, 600].
  EXPECT_EQ(r.volumes[0].occupancy.index, (V{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(r.volumes[1].occupancy.index, (V{5, 6, 7, 8, 9}));
  CountsRequest g;
  g.query.t0 = 0, g.query.t1 = 600;
  const auto rg = count(set, g);
  ASSERT_EQ(grid_columns(270), 1080);
  ASSERT_EQ(rg.volumes.size(), 4u);
  EXPECT_EQ(rg.volumes[0].id, "r270c0l10");
  EXPECT_EQ(rg.volumes[1].id, "r270c1l10");
  EXPECT_EQ(rg.volumes[2].id, "r270c1078l10");
  EXPECT_EQ(rg.volumes[3].id, "r270c1079l10");
  EXPECT_EQ(rg.volumes[3].occupancy.index, (V{1, 2, 3, 4}));  // [179.668, 180): t in [100.4, 300)
  EXPECT_EQ(rg.volumes[0].occupancy.index, (V{5, 6, 7, 8}));  // [-180, -179.667): t in [300, 499.6)
  EXPECT_NEAR(rg.complexity_total.flight_hours, 600.0 / 3600, 1e-12);
}

// Output shapes: JSON fields and the CSV long format.
TEST(CongestionCounts, JsonAndCsv) {
  TrailSetBuilder b;
  b.add("aaaaaa", "CUT", sample(0, -0.25f, 0.5f, fl(150)));
  b.add("aaaaaa", "CUT", sample(750, 0.5f, 1.25f, fl(150)));
  const auto r = count(b.build(nullptr, kNoSplit), request(0, 900, square(0, 0, 1, 1, 100, 200, 0.5)));
  const auto j = r.to_json();
  EXPECT_EQ(j["volumes_kind"], "sectors");
  EXPECT_EQ(j["method"], "interpolated");
  EXPECT_EQ(j["steps"], 15);
  EXPECT_EQ(j["volumes"][0]["id"], "SQ");
  EXPECT_EQ(j["volumes"][0]["occupancy"]["step"], nlohmann::json({4, 5, 6, 7, 8}));
  EXPECT_EQ(j["volumes"][0]["max_occupancy"], 1);
  EXPECT_EQ(j["hotspots"][0]["volume"], "SQ");
  EXPECT_EQ(j["hotspots"][0]["flights"][0]["callsign"], "CUT");
  std::ostringstream csv;
  r.write_csv(csv);
  EXPECT_EQ(csv.str(),
            "volume,series,index,start,end,value\n"
            "SQ,occupancy,4,240,300,1\nSQ,occupancy,5,300,360,1\nSQ,occupancy,6,360,420,1\n"
            "SQ,occupancy,7,420,480,1\nSQ,occupancy,8,480,540,1\n"
            "SQ,entries,0,0,900,1\n");
  std::ostringstream hcsv;
  r.write_hotspots_csv(hcsv);
  EXPECT_EQ(hcsv.str(),
            "volume,kind,first_step,last_step,start,end,peak,peak_time,threshold,excess,flights\n"
            "SQ,peak,4,8,240,540,1,240,0.5,0.5,0\n");
}

Error error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "no error";
  return Error(Error::Kind::internal, "", "");
}

// Progress goes through the three stages in order and ends at 1; a cancelled token stops the count
// with Error(cancelled).
TEST(CongestionCounts, ProgressAndCancel) {
  TrailSetBuilder b;
  for (int f = 0; f < 600; ++f) {
    const std::string id = "f" + std::to_string(100000 + f);
    b.add(id, id, sample(0, -1, 0.5f, fl(150)));
    b.add(id, id, sample(600, 2, 0.5f, fl(150)));
  }
  const TrailSet set = b.build(nullptr, kNoSplit);
  std::vector<std::string> stages;
  double last = -1;
  const auto r = count(set, request(0, 900, square(0, 0, 1, 1)), [&](double f, std::string_view st) {
    if (stages.empty() || stages.back() != st) stages.emplace_back(st);
    last = f;
  });
  EXPECT_EQ(stages, (std::vector<std::string>{"inside", "counts", "complexity"}));
  EXPECT_EQ(last, 1.0);
  EXPECT_EQ(r.volumes[0].occupancy.max(), 600u);  // all inside during [200, 400]
  CancelToken cancel;
  cancel.cancel();
  const Error e = error_of([&] { count(set, request(0, 900, square(0, 0, 1, 1)), {}, &cancel); });
  EXPECT_EQ(e.kind(), Error::Kind::cancelled);
}

TEST(CongestionCounts, RequestChecks) {
  const TrailSet set;
  const auto expect = [&](CountsRequest r, const std::string& param, const std::string& message) {
    const Error e = error_of([&] { count(set, r); });
    EXPECT_EQ(e.param(), param);
    EXPECT_EQ(std::string(e.what()), message);
  };
  CountsRequest r;
  expect(r, "t0", "t0 is required: congestion counts need a time window [t0, t1)");
  r.query.t0 = 0;
  expect(r, "t1", "t1 is required: congestion counts need a time window [t0, t1)");
  r.query.t1 = 8 * 86400;
  expect(r, "t1", "t1 - t0 exceeds the longest congestion window of 7 days");
  r.query.t1 = 3600;
  auto s = r;
  s.step_s = 0.5;
  expect(s, "step", "step must lie in [1, 3600] seconds, got 0.5");
  s = r;
  s.duration_s = 30;
  expect(s, "duration", "duration must lie in [60, 3600] seconds, got 30");
  s = r;
  s.peak = -1;
  expect(s, "peak", "peak must be a number of flights >= 0, got -1");
  s = r;
  s.sectors = square(0, 0, 1, 1);
  s.query.bbox = BBox{};
  expect(s, "bbox", "bbox selects the grid's extent; it does not apply to sectors");
  s = r;
  s.query.on_ground = false;
  expect(s, "on_ground", "on_ground does not apply to congestion counts (trajectories are airborne)");
  s = r;
  s.query.t1 = 86400 * 7;
  s.step_s = 1;
  const Error big = error_of([&] { count(set, s); });
  EXPECT_EQ(big.kind(), Error::Kind::payload_too_large);
  EXPECT_EQ(big.param(), "step");
  EXPECT_EQ(std::string(big.what()),
            "the window holds 604800 counting periods, more than the limit of 100000; use a longer step or a "
            "shorter window");
  const Error m = error_of([] { parse_method("both"); });
  EXPECT_EQ(std::string(m.what()), "method must be 'interpolated' or 'samples', got 'both'");
  const Error pc = error_of([] { parse_counts_request({{"t0", "0"}, {"t1", "3600"}, {"step", "abc"}}); });
  EXPECT_EQ(pc.param(), "step");
  EXPECT_EQ(std::string(pc.what()), "step: 'abc' is not a number");
  const auto ok = parse_counts_request({{"t0", "0"},
                                        {"t1", "3600"},
                                        {"step", "120"},
                                        {"duration", "300"},
                                        {"method", "samples"},
                                        {"peak", "10"},
                                        {"complexity", "false"}});
  EXPECT_EQ(ok.step_s, 120);
  EXPECT_EQ(ok.duration_s, 300);
  EXPECT_EQ(ok.method, Method::samples);
  EXPECT_EQ(ok.peak, 10);
  EXPECT_FALSE(ok.complexity);
}

}  // namespace
}  // namespace trailscope::congestion
