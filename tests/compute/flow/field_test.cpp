// Sector fields of traffic (trailscope/flow/field.hpp) against a brute-force computation written here:
// every segment cut into many short pieces, each dropped whole into the cell of its midpoint.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "trailscope/core/error.hpp"
#include "trailscope/flow/field.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::flow {
namespace {

constexpr double kWorld = 4294967296.0;

/// Flights of random straight-ish legs over western Europe, a sample a minute, some with gaps.
TrailSet random_traffic(int flights, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> lon(-8, 20), lat(38, 58), turn(-0.4, 0.4), spd(0.05, 0.25);
  TrailSetBuilder b;
  for (int f = 0; f < flights; ++f) {
    double x = lon(rng), y = lat(rng), hd = std::uniform_real_distribution<double>(0, 2 * M_PI)(rng);
    const double v = spd(rng);
    double t = 1514764800 + 60.0 * f;
    const int n = 20 + f % 30;
    char id[8];
    std::snprintf(id, sizeof id, "%06x", 0x400000 + f);
    for (int k = 0; k < n; ++k) {
      Sample s;
      s.t = t, s.lon = static_cast<float>(x), s.lat = static_cast<float>(y), s.alt = 10000;
      b.add(id, "TST" + std::to_string(f), s);
      hd += turn(rng);
      x += v * std::sin(hd), y += v * std::cos(hd);
      t += (k == n / 2 && f % 5 == 0) ? 1200 : 60;  // every fifth flight has a 20-minute hole
    }
  }
  return b.build(nullptr, 1e9);
}

struct Brute {
  std::vector<double> sx, sy, w;
};

/// The field by brute force: segments of consecutive points that pass [t0, t1) and the gap, each cut
/// into `pieces` equal parts; the heading sector from the compass bearing of the Mercator step.
std::vector<Brute> brute(const TrailSet& ts, const Grid& g, int S, double max_gap, double t0, double t1,
                         int pieces) {
  std::vector<Brute> out(S);
  for (auto& b : out) b.sx.assign(g.cells(), 0), b.sy.assign(g.cells(), 0), b.w.assign(g.cells(), 0);
  const auto& P = ts.points();
  for (const Flight& f : ts.flights())
    for (std::size_t i = f.begin; i + 1 < f.end; ++i) {
      const std::size_t j = i + 1;
      if (!(P.t[i] >= t0 && P.t[i] < t1 && P.t[j] >= t0 && P.t[j] < t1)) continue;
      if (P.t[j] - P.t[i] > max_gap) continue;
      const double ax = (ts.merc_x()[i] - g.x0) / g.cell, ay = (ts.merc_y()[i] - g.y0) / g.cell;
      const double bx = (ts.merc_x()[j] - g.x0) / g.cell, by = (ts.merc_y()[j] - g.y0) / g.cell;
      const double len = std::hypot(bx - ax, by - ay);
      if (len == 0) continue;
      double deg = std::atan2(bx - ax, ay - by) * 180 / M_PI;  // bearing: 0 when moving to smaller y
      if (deg < 0) deg += 360;
      const int s = static_cast<int>(std::lround(deg / (360.0 / S))) % S;
      for (int k = 0; k < pieces; ++k) {
        const double u = (k + 0.5) / pieces;
        const double x = ax + u * (bx - ax), y = ay + u * (by - ay);
        if (x < 0 || y < 0 || x >= g.nx || y >= g.ny) continue;
        const std::size_t c =
            static_cast<std::size_t>(std::floor(y)) * g.nx + static_cast<std::size_t>(std::floor(x));
        out[s].w[c] += len / pieces;
        out[s].sx[c] += (bx - ax) / pieces;
        out[s].sy[c] += (by - ay) / pieces;
      }
    }
  return out;
}

void expect_matches_brute(const VectorField& f, const std::vector<Brute>& b, double tol) {
  ASSERT_EQ(f.sectors.size(), b.size());
  double total = 0;
  for (std::size_t s = 0; s < b.size(); ++s)
    for (std::size_t c = 0; c < f.grid.cells(); ++c) {
      ASSERT_NEAR(f.sectors[s].w[c], b[s].w[c], tol + 1e-5 * b[s].w[c]) << "sector " << s << " cell " << c;
      ASSERT_NEAR(f.sectors[s].sx[c], b[s].sx[c], tol + 1e-5 * b[s].w[c]) << "sector " << s << " cell " << c;
      ASSERT_NEAR(f.sectors[s].sy[c], b[s].sy[c], tol + 1e-5 * b[s].w[c]) << "sector " << s << " cell " << c;
      total += b[s].w[c];
    }
  EXPECT_GT(total, 100.0);  // the comparison is not vacuous
}

TEST(TrafficField, SectorsMatchBruteForce) {
  const TrailSet ts = random_traffic(120, 7);
  FieldParams p;
  p.grid = 48, p.sectors = 8, p.smooth = 0, p.max_gap_seconds = 600;
  const VectorField f = traffic_field(ts, Query{}, p);
  EXPECT_TRUE(f.grid.geographic);
  EXPECT_LE(std::max(f.grid.nx, f.grid.ny), 48);
  // 20000 pieces per segment: a piece straddling a cell edge misplaces at most len/20000 there.
  expect_matches_brute(f, brute(ts, f.grid, 8, 600, -1e300, 1e300, 20000), 2e-3);
}

TEST(TrafficField, WindowAndBBoxSelectLikeTheOtherVerbs) {
  const TrailSet ts = random_traffic(120, 11);
  FieldParams p;
  p.grid = 32, p.sectors = 6, p.smooth = 0, p.max_gap_seconds = 1e9;
  Query q;
  q.t0 = 1514764800 + 1800, q.t1 = 1514764800 + 5400;
  q.bbox = BBox{0, 45, 12, 55};
  const VectorField f = traffic_field(ts, q, p);
  // The grid covers the bbox (Web Mercator), the longer side 32 cells.
  EXPECT_NEAR(f.grid.x0, (0 + 180.0) / 360.0 * kWorld, 1.0);
  EXPECT_NEAR(f.grid.lon(0), 0.0, 1e-6);
  EXPECT_NEAR(f.grid.lat(0), 55.0, 1e-6);
  // Points outside the bbox fail the filter, so their segments are dropped (as the density does).
  std::vector<Brute> b(6);
  {
    // Brute force with the bbox: only pairs whose both points are inside.
    TrailSetBuilder tb;
    const auto& P = ts.points();
    for (std::size_t fi = 0; fi < ts.num_flights(); ++fi) {
      const Flight& fl = ts.flights()[fi];
      for (std::size_t i = fl.begin; i < fl.end; ++i) {
        if (!q.bbox->contains(P.lat[i], P.lon[i])) continue;
        Sample s;
        s.t = P.t[i], s.lat = P.lat[i], s.lon = P.lon[i], s.alt = P.alt[i];
        // A flight id per run of inside points: an outside point splits the flight as the filter does.
        const bool prev_in = i > fl.begin && q.bbox->contains(P.lat[i - 1], P.lon[i - 1]);
        static int run = 0;
        if (!prev_in) ++run;
        char id[8];
        std::snprintf(id, sizeof id, "%06x", run);
        tb.add(id, "", s);
      }
    }
    const TrailSet inside = tb.build(nullptr, 1e9);
    b = brute(inside, f.grid, 6, 1e9, *q.t0, *q.t1, 20000);
  }
  expect_matches_brute(f, b, 2e-3);
}

TEST(TrafficField, OpposingFlowsDoNotCancel) {
  TrailSetBuilder b;
  for (int k = 0; k <= 20; ++k) {  // east along 50°N, and back west on the same track
    Sample s;
    s.t = 1514764800 + 60.0 * k, s.lat = 50, s.lon = static_cast<float>(2 + 0.5 * k), s.alt = 10000;
    b.add("aaaaaa", "EAST", s);
    s.lon = static_cast<float>(12 - 0.5 * k);
    b.add("bbbbbb", "WEST", s);
  }
  const TrailSet ts = b.build(nullptr, 1e9);
  FieldParams p;
  p.grid = 40, p.sectors = 8, p.smooth = 0;
  const VectorField f = traffic_field(ts, Query{}, p);
  double east_w = 0, east_sx = 0, west_w = 0, west_sx = 0, other = 0;
  for (std::size_t c = 0; c < f.grid.cells(); ++c) {
    east_w += f.sectors[2].w[c], east_sx += f.sectors[2].sx[c];  // sector 2: 90° (east)
    west_w += f.sectors[6].w[c], west_sx += f.sectors[6].sx[c];  // sector 6: 270° (west)
    for (int s : {0, 1, 3, 4, 5, 7}) other += f.sectors[s].w[c];
  }
  EXPECT_GT(east_w, 30);
  EXPECT_NEAR(east_w, west_w, 1e-3 * east_w);
  EXPECT_NEAR(east_sx, east_w, 1e-3 * east_w);   // all pointing east
  EXPECT_NEAR(west_sx, -west_w, 1e-3 * west_w);  // all pointing west
  EXPECT_EQ(other, 0);
  EXPECT_DOUBLE_EQ(f.sector_heading(2), 90);
}

TEST(TrafficField, SectorOfHeading) {
  EXPECT_EQ(sector_of(0, 8), 0);
  EXPECT_EQ(sector_of(22.4, 8), 0);
  EXPECT_EQ(sector_of(22.6, 8), 1);
  EXPECT_EQ(sector_of(359, 8), 0);
  EXPECT_EQ(sector_of(-90, 8), 6);
  EXPECT_EQ(sector_of(180, 4), 2);
}

TEST(TrafficField, BadParametersAndEmptyQueries) {
  const TrailSet ts = random_traffic(5, 1);
  FieldParams p;
  p.grid = 4;
  try {
    traffic_field(ts, Query{}, p);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.param(), "grid");
  }
  p = FieldParams{};
  p.sectors = 17;
  EXPECT_THROW(traffic_field(ts, Query{}, p), Error);
  Query q;
  q.callsign = "NOPE";
  try {
    traffic_field(ts, q, FieldParams{});
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::unprocessable);
    EXPECT_EQ(e.param(), "query");
  }
}

TEST(UploadedField, ParsesTheDocumentedFormat) {
  const std::string text = R"({"format": "trailscope-flow-field", "version": 1, "width": 3, "height": 2,
    "u": [1, 0, null, 2, 0, 0], "v": [0, 1, 0, 0, -3, 0], "weight": [5, 6, 7, 8, 9, 10]})";
  const VectorField f = parse_field(text);
  ASSERT_EQ(f.sectors.size(), 1u);
  EXPECT_FALSE(f.by_heading);
  EXPECT_FALSE(f.grid.geographic);
  EXPECT_EQ(f.grid.nx, 3);
  EXPECT_EQ(f.grid.ny, 2);
  const SectorField& s = f.sectors[0];
  EXPECT_FLOAT_EQ(s.sx[0], 5);
  EXPECT_FLOAT_EQ(s.sy[0], 0);
  EXPECT_FLOAT_EQ(s.w[0], 5);
  EXPECT_FLOAT_EQ(s.sx[1], 0);
  EXPECT_FLOAT_EQ(s.sy[1], -6);  // v north = −y
  EXPECT_FLOAT_EQ(s.w[2], 0);    // null: no data
  EXPECT_FLOAT_EQ(s.sy[4], 9);   // v = −3 points south = +y
  EXPECT_FLOAT_EQ(s.w[5], 0);    // zero vector: no direction
  EXPECT_TRUE(std::isnan(f.sector_heading(0)));
}

TEST(UploadedField, ErrorsNameTheMember) {
  const auto param_of = [](const std::string& text) {
    try {
      parse_field(text);
    } catch (const Error& e) {
      return std::string(to_string(e.kind())) + ":" + e.param();
    }
    return std::string("none");
  };
  EXPECT_EQ(param_of("[1,2]"), "unsupported_format:field");
  EXPECT_EQ(param_of("{"), "unsupported_format:field");
  EXPECT_EQ(param_of(R"({"format": "x", "version": 1})"), "invalid_argument:format");
  EXPECT_EQ(param_of(R"({"format": "trailscope-flow-field", "version": 2})"), "invalid_argument:version");
  EXPECT_EQ(param_of(R"({"format": "trailscope-flow-field", "version": 1, "width": 1, "height": 2})"),
            "invalid_argument:width");
  EXPECT_EQ(
      param_of(R"({"format": "trailscope-flow-field", "version": 1, "width": 2, "height": 2, "u": [1,2,3]})"),
      "invalid_argument:u");
  EXPECT_EQ(param_of(R"({"format": "trailscope-flow-field", "version": 1, "width": 2, "height": 2,
                          "u": [1,2,3,4], "v": [1,2,3,"a"]})"),
            "invalid_argument:v");
  EXPECT_EQ(param_of(R"({"format": "trailscope-flow-field", "version": 1, "width": 2, "height": 2,
                          "u": [1,2,3,4], "v": [1,2,3,4], "weight": [1,-1,1,1]})"),
            "invalid_argument:weight");
  EXPECT_EQ(param_of(R"({"format": "trailscope-flow-field", "version": 1, "width": 2, "height": 2,
                          "u": [1,2,3,4], "v": [1,2,3,4], "bbox": [0, 50, 0, 40]})"),
            "invalid_argument:bbox");
  EXPECT_EQ(param_of(std::string(limits::kMaxFlowFieldBytes + 1, ' ')), "payload_too_large:field");
}

}  // namespace
}  // namespace trailscope::flow
