// flight_trails on the Europe SO6 day, against runs computed here with plain comparisons on the raw
// columns (not PointFilter), and on small synthetic sets (antimeridian, stationary, errors).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "test_support.hpp"
#include "trailscope/bundling/flight_trails.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/ingest/ingest.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::bundling {
namespace {

constexpr double kDay = 1514764800.0;  // 2018-01-01T00:00:00Z, the day of the SO6 sample
constexpr double kWorld = 4294967296.0;

const TrailSet* europe() {
  static const std::unique_ptr<TrailSet> set = []() -> std::unique_ptr<TrailSet> {
    const auto path = test::shared_data("flights/traffic_europe_20180101_m3.so6.gz");
    if (!std::filesystem::exists(path)) return nullptr;
    return std::make_unique<TrailSet>(ingest::ingest_file(path.string()));
  }();
  return set.get();
}

struct Expected {
  std::vector<std::size_t> flight, points;  // per run
  std::vector<std::uint32_t> first_x;       // merc x of each run's first point
};

/// Runs of points with t in [t0, t1) and (lat, lon) in the closed box, split at gaps > gap.
Expected expected_runs(const TrailSet& ts, double t0, double t1, double w, double s, double e, double n,
                       double gap) {
  Expected out;
  const auto& p = ts.points();
  for (std::size_t fi = 0; fi < ts.num_flights(); ++fi) {
    const Flight& f = ts.flights()[fi];
    std::size_t run = 0, first = 0;
    double last_t = 0;
    auto close = [&] {
      if (run >= 2)
        out.flight.push_back(fi), out.points.push_back(run), out.first_x.push_back(ts.merc_x()[first]);
      run = 0;
    };
    for (std::size_t i = f.begin; i < f.end; ++i) {
      const double lat = p.lat[i], lon = p.lon[i];
      const bool in = p.t[i] >= t0 && p.t[i] < t1 && lat >= s && lat <= n && lon >= w && lon <= e;
      if (!in) {
        close();
        continue;
      }
      if (run > 0 && p.t[i] - last_t > gap) close();
      if (run == 0) first = i;
      ++run, last_t = p.t[i];
    }
    close();
  }
  return out;
}

double merc_y(double lat) {
  const double phi = lat * M_PI / 180;
  return (0.5 - std::log(std::tan(M_PI / 4 + phi / 2)) / (2 * M_PI)) * kWorld;
}

TEST(FlightTrails, EuropeWindowMatchesIndependentRuns) {
  const TrailSet* eu = europe();
  if (!eu) GTEST_SKIP() << "shared data absent";
  Query q;
  q.bbox = BBox{0, 45, 10, 52};
  q.t0 = kDay + 6 * 3600;
  q.t1 = kDay + 12 * 3600;
  for (double gap : {1800.0, 600.0, static_cast<double>(INFINITY)}) {
    SCOPED_TRACE(gap);
    const Expected want = expected_runs(*eu, *q.t0, *q.t1, 0, 45, 10, 52, gap);
    ASSERT_GT(want.flight.size(), 500u);
    const FlightTrails got = flight_trails(*eu, q, 512, gap);
    ASSERT_EQ(got.lines.size(), want.flight.size());
    EXPECT_EQ(got.flight, want.flight);
    for (std::size_t r = 0; r < want.flight.size(); ++r) {
      ASSERT_EQ(got.lines.end(r) - got.lines.begin(r), want.points[r]) << r;
      ASSERT_EQ(got.lines.x[got.lines.begin(r)], static_cast<double>(want.first_x[r])) << r;
    }
  }
  // The frame is the bbox in Mercator units: 10° wide, 45–52°N tall (taller than wide at 512 px).
  const FlightTrails ft = flight_trails(*eu, q, 512, 1800);
  const double x0 = kWorld * 180 / 360, x1 = kWorld * 190 / 360, y0 = merc_y(52), y1 = merc_y(45);
  ASSERT_GT(y1 - y0, x1 - x0);
  EXPECT_NEAR(ft.frame.to_px_y(y0), 0, 1e-6);
  EXPECT_NEAR(ft.frame.to_px_y(y1), 512, 1e-6);
  EXPECT_NEAR(ft.frame.to_px_x(x0) + ft.frame.to_px_x(x1), 512, 1e-6);  // centred
  EXPECT_NEAR(ft.frame.scale, 512 / (y1 - y0), 1e-15);
  EXPECT_FALSE(ft.frame.flip_y);
  // Every point lies in the view.
  const Polylines px = ft.frame.to_pixels(ft.lines);
  for (std::size_t k = 0; k < px.points(); ++k) {
    ASSERT_GE(px.x[k], -1e-6);
    ASSERT_LE(px.x[k], 512 + 1e-6);
    ASSERT_GE(px.y[k], -1e-6);
    ASSERT_LE(px.y[k], 512 + 1e-6);
  }
}

TEST(FlightTrails, WithoutABoxTheFrameIsTheExtent) {
  const TrailSet* eu = europe();
  if (!eu) GTEST_SKIP() << "shared data absent";
  Query q;
  q.t0 = kDay + 10 * 3600;
  q.t1 = kDay + 11 * 3600;
  const FlightTrails ft = flight_trails(*eu, q, 1024, INFINITY);
  const Expected want = expected_runs(*eu, *q.t0, *q.t1, -180, -90, 180, 90, INFINITY);
  EXPECT_EQ(ft.flight, want.flight);
  const Polylines px = ft.frame.to_pixels(ft.lines);
  const auto [xlo, xhi] = std::minmax_element(px.x.begin(), px.x.end());
  const auto [ylo, yhi] = std::minmax_element(px.y.begin(), px.y.end());
  // The longer side fills the image exactly, the other is centred.
  EXPECT_NEAR(std::max(*xhi - *xlo, *yhi - *ylo), 1024, 1e-6);
  EXPECT_NEAR(*xlo + *xhi, 1024, 1e-6);
  EXPECT_NEAR(*ylo + *yhi, 1024, 1e-6);
}

TrailSet synthetic(const std::vector<std::vector<std::pair<double, double>>>& flights, double dt = 60) {
  TrailSetBuilder b;
  int id = 0;
  for (const auto& f : flights) {
    char icao[8];
    std::snprintf(icao, sizeof icao, "%06x", 0xb00000 + id);
    double t = kDay + 7200.0 * id++;
    for (const auto& [lon, lat] : f) {
      Sample s;
      s.t = t;
      s.lon = static_cast<float>(lon);
      s.lat = static_cast<float>(lat);
      b.add(icao, "SYN", s);
      t += dt;
    }
  }
  return b.build();
}

TEST(FlightTrails, AcrossTheAntimeridianTheRunIsUnwrapped) {
  const TrailSet ts = synthetic({{{178, 10}, {179.5, 10}, {-179.5, 10}, {-178, 10}}});
  const FlightTrails ft = flight_trails(ts, Query{}, 256, 1800);
  ASSERT_EQ(ft.lines.size(), 1u);
  ASSERT_EQ(ft.lines.points(), 4u);
  for (std::size_t k = 1; k < 4; ++k) EXPECT_GT(ft.lines.x[k], ft.lines.x[k - 1]);
  EXPECT_EQ(ft.lines.x[2], ts.merc_x()[2] + kWorld);
  EXPECT_LT(ft.lines.x[3] - ft.lines.x[0], kWorld / 50);  // 4° of longitude, not the whole world
  // A box across 180° spans west .. east + one world.
  Query q;
  q.bbox = BBox{170, 0, -170, 20};
  const FlightTrails boxed = flight_trails(ts, q, 256, 1800);
  // 20° wide, 0–20°N a little taller: y fills the image and x (350°..370° east of 180°W) is centred.
  EXPECT_NEAR(boxed.frame.to_px_y(merc_y(20)), 0, 1e-6);
  EXPECT_NEAR(boxed.frame.to_px_x(kWorld * 350 / 360) + boxed.frame.to_px_x(kWorld * 370 / 360), 256, 1e-6);
}

TEST(FlightTrails, FiltersGapsAndErrors) {
  // 10 samples a minute apart, one 2-hour silence after the 5th.
  TrailSetBuilder b;
  for (int k = 0; k < 10; ++k) {
    Sample s;
    s.t = kDay + 60.0 * k + (k >= 5 ? 7200 : 0);
    s.lon = 5.0f + 0.1f * k;
    s.lat = 50.0f;
    s.alt = k == 2 ? Sample::kUnknown : 10000.0f;
    b.add("abcdef", "GAP", s);
  }
  const TrailSet ts = b.build(nullptr, INFINITY);
  ASSERT_EQ(ts.num_flights(), 1u);
  EXPECT_EQ(flight_trails(ts, Query{}, 256, 1800).lines.size(), 2u);  // split at the silence
  EXPECT_EQ(flight_trails(ts, Query{}, 256, INFINITY).lines.size(), 1u);
  Query alt;
  alt.alt_min = 0;  // point 2 has no altitude: it fails the band and cuts the first run into 0–1 and 3–4
  const FlightTrails cut = flight_trails(ts, alt, 256, 1800);
  EXPECT_EQ(cut.lines.size(), 3u);
  EXPECT_EQ(cut.lines.points(), 2u + 2u + 5u);

  auto error_of = [](auto&& f) {
    try {
      f();
    } catch (const Error& e) {
      return std::string(to_string(e.kind())) + " " + e.param();
    }
    return std::string("none");
  };
  Query none;
  none.t0 = kDay + 86400 * 2;
  none.t1 = kDay + 86400 * 3;
  EXPECT_EQ(error_of([&] { flight_trails(ts, none, 256, 1800); }), "unprocessable query");
  EXPECT_EQ(error_of([&] { flight_trails(ts, Query{}, 256, 0); }), "invalid_argument max_gap");
  EXPECT_EQ(error_of([&] { flight_trails(ts, Query{}, 256, NAN); }), "invalid_argument max_gap");
  // A single matching sample per run makes no polyline.
  Query one;
  one.t0 = kDay;
  one.t1 = kDay + 30;
  EXPECT_EQ(error_of([&] { flight_trails(ts, one, 256, 1800); }), "unprocessable query");
}

}  // namespace
}  // namespace trailscope::bundling
