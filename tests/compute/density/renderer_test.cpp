// The one-call tile API: parameter errors, the shared span and its cache, seams between neighbouring
// tiles, tiles of consecutive zooms, the antimeridian, empty tiles, and backend independence.
#include "trailscope/density/renderer.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <thread>

#include "density_test_util.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/geo/web_mercator.hpp"
#include "trailscope/ocl_info.hpp"

namespace trailscope::density {
namespace {
using geo::TileId;

std::string param_of(const TileRequest& r) {
  try {
    validate(r);
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::invalid_argument);
    return e.param();
  }
  return "";
}

using test::synthetic;

TileRequest request(TileId t, Backend b = Backend::cpu) {
  TileRequest r;
  r.tile = t;
  r.backend = b;
  return r;
}

TEST(Renderer, ErrorsNameTheParameter) {
  TileRequest r = request(TileId{3, 4, 2});
  EXPECT_EQ(param_of(r), "");
  r.tile.z = 23;
  EXPECT_EQ(param_of(r), "z");
  r.tile = TileId{3, 8, 2};
  EXPECT_EQ(param_of(r), "x");
  r.tile = TileId{3, 4, -1};
  EXPECT_EQ(param_of(r), "y");
  r.tile = TileId{3, 4, 2};
  r.size = 300;
  EXPECT_EQ(param_of(r), "size");
  r.size = 512;
  r.cmap = "jet";
  EXPECT_EQ(param_of(r), "cmap");
  r.cmap = "magma";
  r.kernel_radius = limits::kMaxKernelRadiusPx + 1;
  EXPECT_EQ(param_of(r), "kernel_radius");
  r.kernel_radius = -1;
  EXPECT_EQ(param_of(r), "kernel_radius");
  r.kernel_radius = 4;
  r.max_gap_seconds = 0;
  EXPECT_EQ(param_of(r), "max_gap");
  r.max_gap_seconds = NAN;
  EXPECT_EQ(param_of(r), "max_gap");
  DensityRenderer renderer;
  r.cmap = "nope";
  r.max_gap_seconds = 60;
  try {
    renderer.render_tile(synthetic(), "syn", Query{}, r);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.param(), "cmap");
  }
  EXPECT_EQ(renderer.cached_spans(), 0u);  // validation comes before any work
}

TEST(Renderer, TileIsAPngOfTheRightSize) {
  DensityRenderer renderer;
  TileRequest r = request(TileId{4, 8, 5});
  const TileResult res = renderer.render_tile(synthetic(), "syn", Query{}, r);
  EXPECT_FALSE(res.empty);
  EXPECT_GT(res.max_count, 0u);
  EXPECT_EQ(res.path, "cpu");
  EXPECT_GT(res.ms, 0.0);
  const Image img = decode_png(res.png);
  EXPECT_EQ(img.width, 256);
  EXPECT_EQ(img.height, 256);
  r.size = 512;
  EXPECT_EQ(decode_png(renderer.render_tile(synthetic(), "syn", Query{}, r).png).width, 512);
}

TEST(Renderer, EmptyTileIsTransparent) {
  DensityRenderer renderer;
  const TileResult res =
      renderer.render_tile(synthetic(), "syn", Query{}, request(TileId{4, 2, 12}));  // South Pacific
  EXPECT_TRUE(res.empty);
  EXPECT_EQ(res.max_count, 0u);
  const Image img = decode_png(res.png);
  ASSERT_EQ(img.width, 256);
  for (std::size_t i = 3; i < img.rgba.size(); i += 4) ASSERT_EQ(img.rgba[i], 0);
}

TEST(Renderer, OneSpanPerZoomIsCachedAndShared) {
  DensityRenderer renderer;
  bool cached = true;
  const auto a = renderer.span_for(synthetic(), "syn", Query{}, request(TileId{5, 16, 11}), &cached);
  EXPECT_FALSE(cached);
  const auto b = renderer.span_for(synthetic(), "syn", Query{}, request(TileId{5, 15, 10}), &cached);
  EXPECT_TRUE(cached);
  EXPECT_EQ(a.get(), b.get());  // every tile of the zoom shares it
  const auto c = renderer.span_for(synthetic(), "syn", Query{}, request(TileId{6, 32, 22}), &cached);
  EXPECT_FALSE(cached);
  EXPECT_NE(a.get(), c.get());
  Query q;
  q.t0 = 0.0;
  renderer.span_for(synthetic(), "syn", q, request(TileId{5, 16, 11}), &cached);
  EXPECT_FALSE(cached);  // another query, another span
  EXPECT_EQ(renderer.cached_spans(), 3u);
  renderer.forget_dataset("syn");
  EXPECT_EQ(renderer.cached_spans(), 0u);

  // Concurrent requests for one span compute it once.
  std::atomic<int> computed{0};
  std::vector<std::thread> threads;
  for (int k = 0; k < 8; ++k)
    threads.emplace_back([&] {
      bool hit = true;
      renderer.span_for(synthetic(), "syn", Query{}, request(TileId{7, 64, 44}), &hit);
      if (!hit) ++computed;
    });
  for (auto& t : threads) t.join();
  EXPECT_EQ(computed.load(), 1);
}

TEST(Renderer, ZoomsAboveTheCoarseLevelShareItsAggregate) {
  // The synthetic extent is 1046 px wide at zoom 6, so zooms >= 6 estimate from the zoom-5 aggregate:
  // one zoom deeper halves the counts (above the floor of 1).
  const auto span = [](int z) {
    return estimate_span(synthetic(), Query{}, DensityValue::count, z, 256, 0, limits::kFlightGapSeconds,
                         Backend::cpu);
  };
  const SpanStats s5 = span(5), s6 = span(6), s7 = span(7);
  EXPECT_DOUBLE_EQ(s6.hi, s5.hi / 2);
  EXPECT_DOUBLE_EQ(s7.hi, s5.hi / 4);
  EXPECT_DOUBLE_EQ(s7.lo, 1.0);
  EXPECT_EQ(s5.samples, s7.samples);
  DensityRenderer renderer;
  bool cached = true;
  const auto r7 = renderer.span_for(synthetic(), "syn", Query{}, request(TileId{7, 64, 44}), &cached);
  EXPECT_EQ(r7->cdf_values, s7.cdf_values);
  EXPECT_EQ(r7->cdf, s7.cdf);
}

TEST(Renderer, ACoarseAggregateCountedElsewhereGivesTheSameSpan) {
  // A store that counts the coarse aggregate itself (CoarseAggregateFn) and knows only the flights'
  // extents gets the span estimate_span() computes on the points, and the zooms above the coarse level
  // share that one count.
  const TrailSet& full = synthetic();
  const TrailSet outline(PointColumns{}, full.flights());
  Query q;
  q.bbox = BBox{full.lon_min() + 0.1, full.lat_min(), full.lon_max(), full.lat_max() - 0.1};
  for (const DensityValue value : {DensityValue::count, DensityValue::altitude})
    for (const int kernel : {0, 3}) {
      DensityRenderer renderer;
      int counted = 0;
      const CoarseAggregateFn coarse = [&](const Canvas& work, DensityValue v, double gap) {
        ++counted;
        return aggregate_lines(full, q, work, v, gap, Backend::cpu);
      };
      for (const int z : {4, 7, 8}) {
        TileRequest r = request(TileId{z, 0, 0});
        r.value = value, r.kernel_radius = kernel;
        const auto span = renderer.span_for(outline, "outline", q, r, coarse);
        const SpanStats want = estimate_span(full, q, value, z, 256, kernel, r.max_gap_seconds, Backend::cpu);
        EXPECT_EQ(span->cdf_values, want.cdf_values) << "z " << z << " kernel " << kernel;
        EXPECT_EQ(span->cdf, want.cdf);
        EXPECT_EQ(span->lo, want.lo);
        EXPECT_EQ(span->hi, want.hi);
      }
      EXPECT_EQ(counted, kernel == 0 ? 2 : 3) << "zooms 7 and 8 share the coarse aggregate of zoom 5";
    }
  // An aggregate of another size is refused.
  DensityRenderer renderer;
  const CoarseAggregateFn wrong = [](const Canvas&, DensityValue, double) {
    return Aggregate::zeros(3, 3, false);
  };
  EXPECT_THROW(renderer.span_for(outline, "o", Query{}, request(TileId{5, 0, 0}), wrong), Error);
}

TEST(Renderer, SpanIsExactWhereTheExtentFits) {
  // At zoom 2 the whole world is 1024 px, so the span is computed from the very pixels of the tiles:
  // it must equal the span of all 16 tiles' counts put together.
  Raster all;
  all.width = 256;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) {
      AggregateOptions o;
      o.backend = Backend::cpu;
      const Raster r = aggregate(synthetic(), Query{}, Canvas::for_tile(TileId{2, x, y}, 256), o).raster;
      all.values.insert(all.values.end(), r.values.begin(), r.values.end());
    }
  all.height = static_cast<int>(all.values.size() / 256);
  const SpanStats expected = compute_span(all);
  const SpanStats got = estimate_span(synthetic(), Query{}, DensityValue::count, 2, 256, 0,
                                      limits::kFlightGapSeconds, Backend::cpu);
  EXPECT_EQ(got.samples, expected.samples);
  EXPECT_EQ(got.cdf_values, expected.cdf_values);
  EXPECT_EQ(got.cdf, expected.cdf);
}

// Colour distance of two RGBA pixels (max over channels).
int distance(const std::uint8_t* a, const std::uint8_t* b) {
  int d = 0;
  for (int c = 0; c < 4; ++c) d = std::max(d, std::abs(int{a[c]} - int{b[c]}));
  return d;
}

void check_seam(const TrailSet& ts, TileId west, int kernel_radius) {
  const TileId east{west.z, west.x + 1, west.y};
  DensityRenderer renderer;
  TileRequest rw = request(west), re = request(east);
  rw.kernel_radius = re.kernel_radius = kernel_radius;
  rw.max_gap_seconds = re.max_gap_seconds = INFINITY;
  const Image a = decode_png(renderer.render_tile(ts, "k", Query{}, rw).png);
  const TileResult eres = renderer.render_tile(ts, "k", Query{}, re);
  EXPECT_TRUE(eres.span_cached);
  const Image b = decode_png(eres.png);
  AggregateOptions o;
  o.backend = Backend::cpu;
  o.kernel_radius = kernel_radius;
  o.max_gap_seconds = INFINITY;
  const Raster ra = aggregate(ts, Query{}, Canvas::for_tile(west, 256), o).raster;
  const Raster rb = aggregate(ts, Query{}, Canvas::for_tile(east, 256), o).raster;
  // 1. Equal numbers on both sides of the seam get equal colours (one span for both tiles).
  int equal_rows = 0;
  for (int y = 0; y < 256; ++y) {
    const float va = ra.at(255, y), vb = rb.at(0, y);
    if (!std::isnan(va) && va == vb) {
      ++equal_rows;
      EXPECT_EQ(distance(a.pixel(255, y), b.pixel(0, y)), 0) << "row " << y;
    }
  }
  if (kernel_radius == 0) EXPECT_GT(equal_rows, 5) << "the seam test needs data across the seam";
  // 2. The numbers of the two tiles are exactly the two halves of one canvas spanning both (no clipping
  //    artefact, and the smoothing margin carries the neighbour's data).
  const Canvas w = Canvas::for_tile(west, 256);
  const Raster rab =
      aggregate(ts, Query{}, Canvas(w.origin_x(), w.origin_y(), w.pixel_units(), 512, 256), o).raster;
  for (int y = 0; y < 256; ++y)
    for (int x = 0; x < 256; ++x) {
      const float l = rab.at(x, y), r = rab.at(256 + x, y);
      ASSERT_TRUE((std::isnan(l) && std::isnan(ra.at(x, y))) || l == ra.at(x, y)) << x << "," << y;
      ASSERT_TRUE((std::isnan(r) && std::isnan(rb.at(x, y))) || r == rb.at(x, y)) << x << "," << y;
    }
  // 3. So the seam pixels have the colours of the strip shaded in one piece with the zoom's span: the
  //    tiles put side by side are the seamless image, within 1/255 (PNG round trip of equal numbers).
  const auto span = renderer.span_for(ts, "k", Query{}, rw);
  ShadeOptions so;
  so.min_level = effective_min_level(rw);  // the tiles' shading: the count default's floor
  const Image strip = shade(rab, *span, so);
  int worst = 0, opaque = 0;
  for (int y = 0; y < 256; ++y) {
    worst = std::max({worst, distance(a.pixel(255, y), strip.pixel(255, y)),
                      distance(b.pixel(0, y), strip.pixel(256, y))});
    opaque += a.pixel(255, y)[3] != 0;
  }
  EXPECT_LE(worst, 1);
  EXPECT_GT(opaque, 5);
}

TEST(Renderer, NeighbouringTilesHaveNoSeam) {
  check_seam(synthetic(), TileId{6, 32, 22}, 0);  // through the fan around Paris
  check_seam(synthetic(), TileId{6, 32, 22}, 6);  // smoothed: the margin carries the neighbour's data
  if (const TrailSet* eu = test::europe()) check_seam(*eu, TileId{5, 16, 10}, 0);
}

TEST(Renderer, ChildTilesTileTheParentExactly) {
  const TrailSet* eu = test::europe();
  const TrailSet& ts = eu ? *eu : synthetic();
  const TileId parent{4, 8, 5};
  AggregateOptions o;
  o.backend = Backend::cpu;
  o.max_gap_seconds = INFINITY;
  auto counts = [&](const Canvas& c) {
    return density_lines(prepare_line_segments(ts, Query{}, c, DensityValue::count, INFINITY), Backend::cpu);
  };
  // The four children drawn one by one are the 512 px rendering of the parent cut in four.
  const Aggregate big = counts(Canvas::for_tile(parent, 512));
  const Aggregate small = counts(Canvas::for_tile(parent, 256));
  const auto kids = geo::children(parent);
  for (int k = 0; k < 4; ++k) {
    const Aggregate c = counts(Canvas::for_tile(kids[k], 256));
    const int ox = (k % 2) * 256, oy = (k / 2) * 256;
    for (int y = 0; y < 256; ++y)
      for (int x = 0; x < 256; ++x)
        ASSERT_EQ(c.count[static_cast<std::size_t>(y) * 256 + x],
                  big.count[static_cast<std::size_t>(oy + y) * 512 + ox + x]);
  }
  // And each parent pixel relates to its 2×2 children as density_lines.hpp documents:
  //   child(c) − V(P∖c) <= parent(P) <= Σ child,  V(P∖c) = run vertices in P's other children.
  // Here every flight is one run (no query, no gap limit), so the vertices are the interior samples.
  const Canvas grid = Canvas::for_tile(parent, 512);
  std::vector<int> vertices(512 * 512, 0);
  for (const Flight& f : ts.flights())
    for (std::uint32_t i = f.begin + 1; i + 1 < f.end; ++i) {
      const std::int64_t x = (std::int64_t{ts.merc_x()[i]} - grid.origin_x()) / grid.pixel_units();
      const std::int64_t y = (std::int64_t{ts.merc_y()[i]} - grid.origin_y()) / grid.pixel_units();
      if (ts.merc_x()[i] >= grid.origin_x() && ts.merc_y()[i] >= grid.origin_y() && x < 512 && y < 512)
        ++vertices[static_cast<std::size_t>(y) * 512 + x];
    }
  std::uint64_t sum_children = 0, strict = 0;
  for (int y = 0; y < 256; ++y)
    for (int x = 0; x < 256; ++x) {
      auto idx = [&](int k) { return static_cast<std::size_t>(2 * y + k / 2) * 512 + 2 * x + k % 2; };
      const int p = small.count[static_cast<std::size_t>(y) * 256 + x];
      int sum = 0, v_all = 0;
      for (int k = 0; k < 4; ++k) sum += big.count[idx(k)], v_all += vertices[idx(k)];
      for (int k = 0; k < 4; ++k)
        ASSERT_LE(big.count[idx(k)] - (v_all - vertices[idx(k)]), p) << x << "," << y;
      ASSERT_LE(p, sum);
      strict += p < sum;
      sum_children += static_cast<std::uint64_t>(sum);
    }
  EXPECT_GT(small.total_count(), 0u);
  EXPECT_GT(strict, 0u);
  // In total the children hold between 1 and 3 times the parent (a line meets at most 3 of a square's
  // 4 quadrants); for long lines close to 2 (a line is twice as many pixels long at the next zoom).
  const double ratio = static_cast<double>(sum_children) / static_cast<double>(small.total_count());
  EXPECT_GE(ratio, 1.0);
  EXPECT_LE(ratio, 3.0);
  RecordProperty("children_to_parent_ratio", std::to_string(ratio));
}

TEST(Renderer, TokyoToAnchorageShowsOnBothSidesOfTheWorld) {
  // 139.78°E → 149.99°W is 70° the short way, across 180°, and 290° the long way.
  const TrailSet ts = test::polylines({{{139.78, 35.55}, {-149.99, 61.17}}});
  DensityRenderer renderer;
  auto count_at = [&](TileId t, int column) {
    AggregateOptions o;
    o.backend = Backend::cpu;
    const Raster r = aggregate(ts, Query{}, Canvas::for_tile(t, 256), o).raster;
    int n = 0;
    for (int y = 0; y < 256; ++y) n += !std::isnan(r.at(column, y));
    return n;
  };
  EXPECT_GT(count_at(TileId{1, 1, 0}, 255), 0);  // east edge of the eastern hemisphere
  EXPECT_GT(count_at(TileId{1, 0, 0}, 0), 0);    // west edge of the western hemisphere
  EXPECT_EQ(count_at(TileId{1, 1, 0}, 0), 0);    // nothing along the long way round
  EXPECT_EQ(count_at(TileId{1, 0, 0}, 255), 0);
  EXPECT_FALSE(renderer.render_tile(ts, "ta", Query{}, request(TileId{2, 3, 1})).empty);  // 90°E..180°
  EXPECT_FALSE(renderer.render_tile(ts, "ta", Query{}, request(TileId{2, 0, 1})).empty);  // 180°..90°W
  EXPECT_TRUE(renderer.render_tile(ts, "ta", Query{}, request(TileId{2, 1, 1})).empty);
  EXPECT_TRUE(renderer.render_tile(ts, "ta", Query{}, request(TileId{2, 2, 1})).empty);
}

TEST(Renderer, ValuesAndSmoothing) {
  DensityRenderer renderer;
  TileRequest r = request(TileId{4, 8, 5});
  r.value = DensityValue::altitude;
  r.cmap = "viridis";
  r.kernel_radius = 5;
  const TileResult res = renderer.render_tile(synthetic(), "syn", Query{}, r);
  EXPECT_FALSE(res.empty);
  // The means are within the synthetic altitudes (1000 m + 100 m per sample).
  AggregateOptions o;
  o.value = DensityValue::altitude;
  o.backend = Backend::cpu;
  const Raster alt = aggregate(synthetic(), Query{}, Canvas::for_tile(r.tile, 256), o).raster;
  for (float v : alt.values)
    if (!std::isnan(v)) ASSERT_TRUE(v >= 1000.0f && v <= 8200.0f) << v;
  // Smoothing spreads the lines: more pixels hold data.
  o.kernel_radius = 5;
  EXPECT_GT(aggregate(synthetic(), Query{}, Canvas::for_tile(r.tile, 256), o).raster.valid_count(),
            alt.valid_count());
  EXPECT_THROW(
      {
        o.kernel_radius = 40;
        aggregate(synthetic(), Query{}, Canvas::for_tile(r.tile, 256), o);
      },
      Error);
}

TEST(Renderer, BackendsGiveTheSameTile) {
  if (!opencl_available()) GTEST_SKIP() << "no OpenCL device";
  test::ScopedEnv strict("TRAILSCOPE_OPENCL_STRICT", "1");
  DensityRenderer renderer;
  const TrailSet* eu = test::europe();
  const TrailSet& ts = eu ? *eu : synthetic();
  for (DensityValue v : {DensityValue::count, DensityValue::speed}) {
    TileRequest cpu = request(TileId{4, 8, 5}, Backend::cpu), ocl = request(TileId{4, 8, 5}, Backend::opencl);
    cpu.value = ocl.value = v;
    const TileResult a = renderer.render_tile(ts, "eu", Query{}, cpu);
    const TileResult b = renderer.render_tile(ts, "eu", Query{}, ocl);
    EXPECT_EQ(a.path, "cpu");
    EXPECT_EQ(b.path, "opencl");
    EXPECT_EQ(a.png, b.png);  // same bytes
  }
}

TEST(Renderer, RenderCanvasForABoundingBox) {
  RenderOptions o;
  o.aggregate.backend = Backend::cpu;
  o.shade.how = How::log;
  const Image img =
      render_canvas(synthetic(), Query{}, Canvas::for_bbox(geo::LonLatBox{-10, 35, 25, 58}, 400), o);
  EXPECT_EQ(img.width, 400);
  EXPECT_GT(img.height, 300);
  std::size_t opaque = 0;
  for (std::size_t i = 3; i < img.rgba.size(); i += 4) opaque += img.rgba[i] != 0;
  EXPECT_GT(opaque, 1000u);
  o.shade.cmap = "rainbow";
  EXPECT_THROW(render_canvas(synthetic(), Query{}, Canvas::for_bbox(geo::LonLatBox{-10, 35, 25, 58}, 400), o),
               Error);
}

}  // namespace
}  // namespace trailscope::density
