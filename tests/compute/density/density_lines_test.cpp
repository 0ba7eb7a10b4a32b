// The line rasteriser checked as numbers: against hand-counted pixels, against the brute-force
// definition of density_lines.hpp (segment_meets_box) on random and edge-case segments, for the
// window-independence that makes tiles seamless, for the parent/children relation between zooms, and
// for the shared-endpoint rule.
#include "trailscope/density/density_lines.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "density_test_util.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/geo/web_mercator.hpp"
#include "trailscope/trails/point_filter.hpp"
#include "trailscope/trails/time_index.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::density {
namespace {
using test::Seg;

constexpr std::int64_t kWorld = std::int64_t{1} << 32;

std::int32_t at(const Aggregate& a, int x, int y) {
  return a.count[static_cast<std::size_t>(y) * a.width + x];
}

Aggregate draw(const std::vector<Seg>& segs, const Canvas& c) {
  return density_lines(test::prepare(segs, c), Backend::cpu);
}

TEST(DensityLines, HorizontalSegmentCoversExactlyItsPixels) {
  const Canvas c(0, 0, 16, 64, 64);
  // From inside pixel (3, 10) to inside pixel (20, 10): 18 pixels, each once.
  const Aggregate a = draw({{{16 * 3 + 5, 16 * 10 + 8}, {16 * 20 + 2, 16 * 10 + 8}}}, c);
  EXPECT_EQ(a.total_count(), 18u);
  for (int x = 3; x <= 20; ++x) EXPECT_EQ(at(a, x, 10), 1) << x;
  // Ending exactly on the west edge of pixel 21 touches pixel 21 (the edge belongs to it).
  const Aggregate b = draw({{{16 * 3 + 5, 16 * 10 + 8}, {16 * 21, 16 * 10 + 8}}}, c);
  EXPECT_EQ(b.total_count(), 19u);
  EXPECT_EQ(at(b, 21, 10), 1);
  // Along a horizontal pixel edge, the segment lies in the row below the edge (half-open squares).
  const Aggregate e = draw({{{16 * 2, 16 * 5}, {16 * 9 + 1, 16 * 5}}}, c);
  EXPECT_EQ(e.total_count(), 8u);
  for (int x = 2; x <= 9; ++x) EXPECT_EQ(at(e, x, 5), 1);
}

TEST(DensityLines, DiagonalsThroughPixelCorners) {
  const Canvas c(0, 0, 16, 16, 16);
  // Corner to corner: each corner point belongs to the pixel south-east of it, so the walk steps
  // diagonally: (0,0), (1,1), ..., (5,5).
  const Aggregate d = draw({{{0, 0}, {80, 80}}}, c);
  EXPECT_EQ(d.total_count(), 6u);
  for (int k = 0; k <= 5; ++k) EXPECT_EQ(at(d, k, k), 1);
  // The other diagonal, (80,0) → (0,80): open pieces in (4−m, m), corner points in (k, 5−k): 11 pixels.
  const Aggregate e = draw({{{80, 0}, {0, 80}}}, c);
  EXPECT_EQ(e.total_count(), 11u);
  for (int m = 0; m <= 4; ++m) EXPECT_EQ(at(e, 4 - m, m), 1);
  for (int k = 0; k <= 5; ++k) EXPECT_EQ(at(e, k, 5 - k), 1);
  // Reversing a segment does not change its pixels.
  EXPECT_TRUE(draw({{{0, 80}, {80, 0}}}, c).same_numbers(e));
  EXPECT_TRUE(draw({{{80, 80}, {0, 0}}}, c).same_numbers(d));
}

TEST(DensityLines, WalkMatchesTheDefinitionOnRandomSegments) {
  std::mt19937 rng(20240601);
  const std::vector<Canvas> canvases = {
      Canvas(0, 0, 1, 40, 30),                    // one unit per pixel: every endpoint on a corner
      Canvas(1000, 2000, 16, 48, 40),             // power-of-two pixels
      Canvas(-7 * 33, 5 * 33 + 3, 33, 37, 29),    // odd pixel size, negative origin
      Canvas(kWorld - 20 * 64, 100, 64, 40, 40),  // at the east edge of the world
  };
  for (const Canvas& c : canvases) {
    const std::vector<Seg> segs = test::random_segments(rng, c, 300, 0.6);
    const Aggregate a = draw(segs, c);
    const std::vector<std::int32_t> expected = test::brute_counts(segs, c);
    ASSERT_EQ(a.count, expected) << c.describe();
    EXPECT_GT(a.total_count(), 500u) << c.describe();  // the test is not vacuous
  }
}

TEST(DensityLines, EachSegmentTouchesEachPixelOnce) {
  // One segment at a time: every pixel count is 0 or 1.
  std::mt19937 rng(5);
  const Canvas c(0, 0, 8, 32, 32);
  for (const Seg& s : test::random_segments(rng, c, 500, 0.3)) {
    const Aggregate a = draw({s}, c);
    for (std::int32_t v : a.count) ASSERT_LE(v, 1);
  }
}

TEST(DensityLines, PixelsDoNotDependOnTheCanvasWindow) {
  // The seam guarantee: a segment gives the same pixels on a big canvas and on any window of the same
  // grid, however it is clipped.
  std::mt19937 rng(99);
  const Canvas big(-50 * 16, 300 * 16, 16, 96, 80);
  const std::vector<Seg> segs = test::random_segments(rng, big, 2000, 1.0);
  const Aggregate all = draw(segs, big);
  for (int wx : {0, 17, 48, 90})
    for (int wy : {0, 33, 79}) {
      const int w = std::min(31, 96 - wx), h = std::min(23, 80 - wy);
      const Canvas window(big.origin_x() + wx * 16, big.origin_y() + wy * 16, 16, w, h);
      const Aggregate part = draw(segs, window);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) ASSERT_EQ(at(part, x, y), at(all, wx + x, wy + y)) << wx << "," << wy;
    }
}

TEST(DensityLines, ParentPixelIsTheUnionOfItsChildren) {
  // Zoom z+1 halves the pixel: a segment touches a parent pixel iff it touches one of its 4 children,
  // so max(children) <= parent <= sum(children) for every pixel.
  std::mt19937 rng(3);
  const Canvas parent(4096, 8192, 32, 40, 40);
  const Canvas child(4096, 8192, 16, 80, 80);
  const std::vector<Seg> segs = test::random_segments(rng, parent, 3000, 0.5);
  const Aggregate p = draw(segs, parent), c = draw(segs, child);
  std::uint64_t strict = 0;
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 40; ++x) {
      const int k[4] = {at(c, 2 * x, 2 * y), at(c, 2 * x + 1, 2 * y), at(c, 2 * x, 2 * y + 1),
                        at(c, 2 * x + 1, 2 * y + 1)};
      const int sum = k[0] + k[1] + k[2] + k[3], mx = std::max({k[0], k[1], k[2], k[3]});
      ASSERT_LE(mx, at(p, x, y));
      ASSERT_LE(at(p, x, y), sum);
      strict += at(p, x, y) < sum;
    }
  EXPECT_GT(strict, 0u);  // segments crossing several children are counted once in the parent
}

TEST(DensityLines, SharedEndpointsOfARunAreCountedOnce) {
  const Canvas c(0, 0, 10, 30, 10);
  // A run out and back along row 4: pixel of the turn (x = 20) once, others twice; a third segment
  // of zero length at the end adds nothing.
  const MercPoint a{15, 45}, b{205, 45}, back{15, 45};
  LineSegments s = LineSegments::for_canvas(c, false);
  append_segment(s, c, a, b, false);
  append_segment(s, c, b, back, true);
  append_segment(s, c, back, back, true);
  const Aggregate r = density_lines(s, Backend::cpu);
  for (int x = 1; x <= 19; ++x) EXPECT_EQ(at(r, x, 4), 2) << x;
  EXPECT_EQ(at(r, 20, 4), 1);
  EXPECT_EQ(r.total_count(), 39u);
  // The same zero-length segment starting a run counts its pixel.
  LineSegments z = LineSegments::for_canvas(c, false);
  append_segment(z, c, a, a, false);
  EXPECT_EQ(density_lines(z, Backend::cpu).total_count(), 1u);
  // A continuing segment whose first endpoint is outside the canvas has no first pixel to leave out.
  LineSegments o = LineSegments::for_canvas(c, false);
  append_segment(o, c, MercPoint{-35, 45}, MercPoint{35, 45}, true);
  EXPECT_EQ(density_lines(o, Backend::cpu).total_count(), 4u);
}

TEST(DensityLines, HugeSegmentsAndCanvasesFarAway) {
  // Segments crossing half the world seen through small canvases of fine pixels (zoom-22-like), and
  // canvases the segments miss entirely.
  std::mt19937 rng(17);
  std::uniform_int_distribution<std::int64_t> u(0, kWorld - 1);
  std::vector<Seg> segs;
  for (int k = 0; k < 40; ++k) segs.push_back(Seg{{u(rng), u(rng)}, {u(rng), u(rng)}});
  segs.push_back(Seg{{0, kWorld / 2}, {kWorld / 2 - 1, kWorld / 2}});  // along a row, half the world
  segs.push_back(Seg{{kWorld / 4, 0}, {kWorld / 4, kWorld - 1}});      // pole to pole
  for (int k = 0; k < 12; ++k) {
    const Seg& s = segs[static_cast<std::size_t>(k)];
    // A window centred on the segment's midpoint, 4 units per pixel.
    const std::int64_t mx = (s.a.x + s.b.x) / 2, my = (s.a.y + s.b.y) / 2;
    for (std::int64_t p : {4, 64, 4096}) {
      const Canvas c(mx - 20 * p, my - 15 * p, p, 40, 30);
      ASSERT_EQ(draw(segs, c).count, test::brute_counts(segs, c)) << c.describe();
    }
  }
  const Canvas nowhere(kWorld / 2 + 12345, -kWorld, 4, 64, 64);  // north of the world
  EXPECT_EQ(draw(segs, nowhere).total_count(), 0u);
}

TEST(DensityLines, AntimeridianSegmentsAppearOnBothSides) {
  // 179°E → 179°W is 2° long the short way, across 180°: with a world canvas it shows at both edges.
  const std::int64_t y = geo::lat_to_merc_y(40.0);
  const Seg s{{geo::lon_to_merc_x(179.0), y}, {geo::lon_to_merc_x(-179.0), y}};
  const Canvas world(0, 0, kWorld / 512, 512, 512);
  const Aggregate a = draw({s}, world);
  const int row = static_cast<int>(y / (kWorld / 512));
  EXPECT_EQ(at(a, 511, row), 1);
  EXPECT_EQ(at(a, 0, row), 1);
  EXPECT_EQ(a.total_count(), 4u);  // ±1.42 px on each side of the edge: pixels 510, 511 | 0, 1
  EXPECT_EQ(a.count, test::brute_counts({s}, world));
  // A canvas reaching beyond 180°E (a margin, or a bbox across the meridian) sees the wrapped copy.
  const Canvas east(kWorld - 8 * (kWorld / 512), 0, kWorld / 512, 16, 512);
  const Aggregate e = draw({s}, east);
  EXPECT_EQ(e.total_count(), 4u);
  EXPECT_EQ(at(e, 7, row) + at(e, 8, row), 2);
}

TEST(DensityLines, ValuesAreMeansOfSegmentValues) {
  const Canvas c(0, 0, 10, 10, 10);
  LineSegments s = LineSegments::for_canvas(c, true);
  append_segment(s, c, {5, 5}, {95, 5}, false, 1000.0);
  append_segment(s, c, {5, 5}, {5, 95}, false, 3000.5);
  append_segment(s, c, {55, 5}, {55, 95}, false, NAN);  // counted, no value
  const Aggregate a = density_lines(s, Backend::cpu);
  EXPECT_DOUBLE_EQ(a.mean(0, 0), 2000.25);
  EXPECT_DOUBLE_EQ(a.mean(9, 0), 1000.0);
  EXPECT_DOUBLE_EQ(a.mean(0, 9), 3000.5);
  EXPECT_DOUBLE_EQ(a.mean(5, 0), 1000.0);  // the NaN segment adds to count only
  EXPECT_EQ(at(a, 5, 0), 2);
  EXPECT_TRUE(std::isnan(a.mean(5, 5)));
  EXPECT_EQ(at(a, 5, 5), 1);
}

TEST(DensityLines, PreparedFromTrailsHonoursQueryGapAndRuns) {
  // Two flights along 10°N: one straight across, one with a point south of a query box.
  TrailSetBuilder b;
  auto add = [&](const char* icao, double t, double lon, double lat) {
    Sample s;
    s.t = t, s.lon = static_cast<float>(lon), s.lat = static_cast<float>(lat), s.alt = 1000;
    b.add(icao, "", s);
  };
  add("aaaaaa", 0, 1, 10), add("aaaaaa", 60, 5, 10), add("aaaaaa", 120, 9, 10);
  add("bbbbbb", 0, 1, 10.5), add("bbbbbb", 60, 5, 5.5), add("bbbbbb", 120, 9, 10.5);
  add("cccccc", 0, 1, 11), add("cccccc", 5000, 9, 11);  // 5000 s gap
  const TrailSet ts = b.build(nullptr, 1e9);            // do not split at the gap
  const Canvas c = Canvas::for_bbox(geo::LonLatBox{0, 0, 10, 12}, 200);
  const Query all;
  Query box;
  box.bbox = BBox{0, 8, 10, 12};  // excludes b's middle point, so both of b's segments go
  const LineSegments s_all = prepare_line_segments(ts, all, c, DensityValue::count);
  const LineSegments s_box = prepare_line_segments(ts, box, c, DensityValue::count);
  const LineSegments s_nogap = prepare_line_segments(ts, all, c, DensityValue::count, INFINITY);
  EXPECT_EQ(s_all.size(), 4u);  // a: 2, b: 2, c: 0 (gap)
  EXPECT_EQ(s_box.size(), 2u);
  EXPECT_EQ(s_nogap.size(), 5u);
  // Flight a is one run: its pixels sum to the pixels of one straight line, the vertex counted once.
  LineSegments straight = LineSegments::for_canvas(c, false);
  append_segment(straight, c, {ts.merc_x()[0], ts.merc_y()[0]}, {ts.merc_x()[2], ts.merc_y()[2]}, false);
  Query only_a;
  only_a.icao24 = {"aaaaaa"};
  EXPECT_EQ(
      density_lines(prepare_line_segments(ts, only_a, c, DensityValue::count), Backend::cpu).total_count(),
      density_lines(straight, Backend::cpu).total_count());
  EXPECT_THROW(prepare_line_segments(ts, all, c, DensityValue::count, 0.0), Error);
}

// WHAT IS DRAWN, written from density_lines.hpp without the time index, the flights' zone map or chunks:
// every segment of every flight, both samples passing the query, within the gap, a run's later segments
// leaving out their first pixel; the walk is append_segment's (checked against the definition above).
LineSegments drawn_by_definition(const TrailSet& ts, const Query& q, const Canvas& c, DensityValue v,
                                 double max_gap) {
  LineSegments out = LineSegments::for_canvas(c, v != DensityValue::count);
  const PointFilter passes(q);
  const auto& p = ts.points();
  for (const Flight& f : ts.flights()) {
    if (!q.matches_flight_ids(f)) continue;
    bool prev_drawn = false;
    for (std::uint32_t i = f.begin + 1; i < f.end; ++i) {
      const bool draw = passes(p, i - 1) && passes(p, i) && p.t[i] - p.t[i - 1] <= max_gap;
      if (draw) {
        const float* col = v == DensityValue::altitude ? p.alt.data() : p.speed.data();
        const float a = col[i - 1], b = col[i];
        const double value = std::isnan(a) ? b : std::isnan(b) ? a : 0.5 * (double{a} + double{b});
        append_segment(out, c, {ts.merc_x()[i - 1], ts.merc_y()[i - 1]}, {ts.merc_x()[i], ts.merc_y()[i]},
                       prev_drawn, value);
      }
      prev_drawn = draw;
    }
  }
  return out;
}

TEST(DensityLines, TrailsDrawnInOnePassAsByTheDefinition) {
  // 700 flights of 40 samples at uneven intervals (5–200 s, some over the gap), enough for the parallel
  // chunks: flights along the edges of the canvases (the latitude zone map's boundaries), a few across
  // 180°, unknown altitudes. Each window and filter gives the same numbers by the definition, by
  // prepare_line_segments + density_lines_ref, and by aggregate_lines' one pass.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  TrailSetBuilder b;
  const Canvas tile = Canvas::for_tile(geo::TileId{6, 33, 22}, 256);
  const double tile_north = geo::merc_y_to_lat(static_cast<double>(tile.origin_y()));
  const double tile_south = geo::merc_y_to_lat(static_cast<double>(tile.end_y()));
  const double tile_west = geo::merc_x_to_lon(static_cast<double>(tile.origin_x()));
  for (int k = 0; k < 700; ++k) {
    const std::string icao = "f" + std::to_string(100000 + k);
    // A third fly due east or west along the tile's north or south edge, within a pixel (0.02°) on either
    // side of it; a few cross 180°.
    const int kind = k % 12;
    double lat = kind < 4   ? tile_north + (u(rng) - 0.5) * 0.02
                 : kind < 8 ? tile_south + (u(rng) - 0.5) * 0.02
                            : -60 + 120 * u(rng);
    const double climb = kind < 8 ? 0.0 : 1.0;
    double lon = kind == 11 ? 179.5 : kind < 8 ? tile_west + 6 * u(rng) : -180 + 360 * u(rng);
    const double heading = 2 * M_PI * u(rng), step = kind < 8 ? 0.01 : 0.3;
    double t = 1000 * u(rng);
    for (int i = 0; i < 40; ++i) {
      Sample s;
      s.t = t, s.lat = static_cast<float>(lat), s.lon = static_cast<float>(lon);
      s.alt = u(rng) < 0.1 ? NAN : static_cast<float>(10000 * u(rng));
      s.speed = static_cast<float>(250 * u(rng));
      b.add(icao, "", s);
      t += u(rng) < 0.05 ? 2000 : 5 + 195 * u(rng);
      lat = std::clamp(lat + climb * step * std::sin(heading) * u(rng), -80.0, 80.0);
      lon += step * std::cos(heading) * u(rng);
      if (lon >= 180) lon -= 360;
    }
  }
  const TrailSet ts = b.build(nullptr, 1e9);  // kept whole: the gaps are the rasteriser's to skip
  ASSERT_TRUE(ts.time_index().valid());
  ASSERT_GE(ts.num_points(), 20000u);

  std::vector<Query> queries(5);
  queries[1].t0 = 1500, queries[1].t1 = 5000;    // a window inside most flights
  queries[2].t0 = 3333.5, queries[2].t1 = 3400;  // shorter than most sample intervals
  queries[3].alt_min = 2000, queries[3].alt_max = 8000;
  queries[4].t0 = 0, queries[4].t1 = 2500, queries[4].alt_min = 100;
  const Canvas world = Canvas::for_tile(geo::TileId{0, 0, 0}, 512);
  const Canvas wide = Canvas::for_tile(geo::TileId{2, 1, 1}, 256, 3);
  int drawn = 0;
  for (const Canvas* c : {&tile, &world, &wide})
    for (const Query& q : queries)
      for (DensityValue v : {DensityValue::count, DensityValue::altitude}) {
        const double gap = v == DensityValue::count ? 600.0 : INFINITY;
        const Aggregate want = density_lines_ref(drawn_by_definition(ts, q, *c, v, gap));
        const LineSegments prepared = prepare_line_segments(ts, q, *c, v, gap);
        EXPECT_TRUE(density_lines_ref(prepared).same_numbers(want)) << q.canonical();
        std::size_t n = 0;
        EXPECT_TRUE(aggregate_lines(ts, q, *c, v, gap, Backend::cpu, &n).same_numbers(want)) << q.canonical();
        EXPECT_EQ(n, prepared.size());
        drawn += want.total_count() > 0;
      }
  EXPECT_EQ(drawn, 30);  // every case draws something
}

TEST(DensityLines, ParsesValueNames) {
  EXPECT_EQ(parse_density_value("altitude"), DensityValue::altitude);
  try {
    parse_density_value("height", "value");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.param(), "value");
  }
}

}  // namespace
}  // namespace trailscope::density
