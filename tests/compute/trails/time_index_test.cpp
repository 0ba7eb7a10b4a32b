// The time index (trails/time_index.hpp) and the reads that use it: the window summary, the window
// quality and the density tile's segment walk, against the plain computations on random windows, on the
// real Europe SO6 day and on a generated fleet. The index's own counts are checked against a brute-force
// count of the points written here.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>

#include <gtest/gtest.h>

#include "test_support.hpp"
#include "trailscope/density/aggregate.hpp"
#include "trailscope/density/canvas.hpp"
#include "trailscope/ingest/demo_traffic.hpp"
#include "trailscope/ingest/ingest.hpp"
#include "trailscope/trails/quality.hpp"
#include "trailscope/trails/summary.hpp"
#include "trailscope/trails/time_index.hpp"

namespace trailscope {
namespace {

std::filesystem::path so6_path() {
  return test::shared_data("flights/traffic_europe_20180101_m3.so6.gz");
}
std::filesystem::path vega_data() {
  return test::source_dir() / "web/node_modules/vega-datasets/data";
}

const TrailSet& europe() {
  static const TrailSet set = ingest::ingest_file(so6_path().string(), {});
  return set;
}

// Three days of a 400-aircraft fleet sampled every 20–90 s.
const TrailSet& fleet() {
  static const TrailSet set = [] {
    ingest::DemoOptions o;
    o.airports_csv = (vega_data() / "airports.csv").string();
    o.routes_csv = (vega_data() / "flights-airport.csv").string();
    o.aircraft = 400, o.days = 3, o.seed = 11;
    o.sample_min_s = 20, o.sample_max_s = 90;
    return ingest::generate_demo_traffic(o);
  }();
  return set;
}

// Equal summaries: every field (the speed mean is rounded to 1e-6 m/s, so its summation order does not show).
void expect_same(const Summary& fast, const Summary& plain, const std::string& what) {
  SCOPED_TRACE(what);
  EXPECT_EQ(fast.to_json(), plain.to_json());
}

// Random windows over a set: whole hours, arbitrary spans, one-sided, outside the data, the whole set.
std::vector<Query> windows(const TrailSet& set, std::uint32_t seed, int n) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const double lo = set.t_min(), hi = set.t_max(), span = hi - lo;
  std::vector<Query> out;
  out.push_back({});  // the whole set
  for (int i = 0; i < n; ++i) {
    Query q;
    const double start = lo - 0.05 * span + u(rng) * 1.1 * span;
    switch (i % 6) {
      case 0:  // whole hours
        q.t0 = std::floor(start / 3600) * 3600, q.t1 = *q.t0 + 3600 * (1 + static_cast<int>(u(rng) * 30));
        break;
      case 1:  // one hour, anywhere
        q.t0 = start, q.t1 = start + 3600;
        break;
      case 2:  // a random span
        q.t0 = start, q.t1 = start + u(rng) * span;
        break;
      case 3:  // only a start
        q.t0 = start;
        break;
      case 4:  // only an end
        q.t1 = start;
        break;
      default:  // minutes
        q.t0 = std::floor(start / 60) * 60, q.t1 = *q.t0 + 60 * (1 + static_cast<int>(u(rng) * 200));
        break;
    }
    if (q.t0 && q.t1 && !(*q.t1 > *q.t0)) continue;
    out.push_back(q);
  }
  return out;
}

void check_summaries(const TrailSet& set, std::uint32_t seed, int n) {
  ASSERT_TRUE(set.time_index().valid());
  const int bins[] = {1, 24, 96, 200, 1000};
  int k = 0;
  for (const Query& q : windows(set, seed, n)) {
    SummaryOptions o;
    o.bins = bins[k % 5];
    o.alt_unit = k % 2 ? AltUnit::m : AltUnit::ft;
    o.top_callsigns = k % 3 ? 10 : 100;
    ++k;
    expect_same(summarize(set, q, o), summarize_scan(set, q, o),
                q.canonical() + " bins " + std::to_string(o.bins));
  }
}

// The index's buckets and fine cells against a count of every point, and its flight range against the
// flights' extents.
void check_index(const TrailSet& set) {
  const TimeIndex& ix = set.time_index();
  ASSERT_TRUE(ix.valid());
  const auto& t = set.points().t;
  std::vector<std::uint64_t> per_bucket(ix.buckets().size()), per_cell(ix.fine_counts().size());
  for (double v : t) {
    ++per_bucket[static_cast<std::size_t>((v - ix.origin()) / ix.bucket_seconds())];
    ++per_cell[static_cast<std::size_t>((v - ix.origin()) / ix.fine_seconds())];
  }
  for (std::size_t b = 0; b < per_bucket.size(); ++b) EXPECT_EQ(ix.buckets()[b].points, per_bucket[b]) << b;
  for (std::size_t c = 0; c < per_cell.size(); ++c) EXPECT_EQ(ix.fine_counts()[c], per_cell[c]) << c;
  for (const Query& q : windows(set, 5, 60)) {
    const double t0 = q.t0.value_or(-INFINITY), t1 = q.t1.value_or(INFINITY);
    const auto [first, last] = ix.flight_range(t0, t1);
    for (std::size_t f = 0; f < set.num_flights(); ++f) {
      const Flight& fl = set.flights()[f];
      const bool meets = fl.t_max >= t0 && fl.t_min < t1;
      if (meets) EXPECT_TRUE(f >= first && f < last) << q.canonical() << " flight " << f;
    }
  }
}

void check_quality_windows(const TrailSet& set) {
  for (const Query& q : windows(set, 9, 40)) {
    const QualityReport a = window_quality(set, q.t0.value_or(-INFINITY), q.t1.value_or(INFINITY));
    const QualityReport b = check_quality(set, q);
    EXPECT_EQ(a.to_json(), b.to_json()) << q.canonical();
  }
}

// Count tiles with the index against the same flights in reverse order (no index: not in start order),
// whose walk visits every flight from its first point.
void check_tiles(const TrailSet& set, const geo::LonLatBox& box) {
  std::vector<Flight> reversed(set.flights().rbegin(), set.flights().rend());
  const TrailSet plain(set.points(), reversed);
  ASSERT_FALSE(plain.time_index().valid());
  const density::Canvas canvas = density::Canvas::for_bbox(box, 512);
  density::AggregateOptions o;
  o.backend = Backend::cpu;
  int nonempty = 0;
  for (const Query& q : windows(set, 13, 12)) {
    const auto a = density::aggregate(set, q, canvas, o), b = density::aggregate(plain, q, canvas, o);
    ASSERT_EQ(a.raster.values.size(), b.raster.values.size());
    EXPECT_EQ(0, std::memcmp(a.raster.values.data(), b.raster.values.data(), a.raster.values.size() * 4))
        << q.canonical();
    EXPECT_EQ(a.max_count, b.max_count);
    EXPECT_EQ(a.segments, b.segments);
    nonempty += a.max_count > 0;
  }
  EXPECT_GT(nonempty, 3);
}

class EuropeIndex : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(so6_path())) GTEST_SKIP() << so6_path() << " is absent";
  }
};
class FleetIndex : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(vega_data() / "airports.csv"))
      GTEST_SKIP() << "vega-datasets not installed (cd web && npm ci): " << vega_data();
  }
};

TEST_F(EuropeIndex, CountsMatchTheirPoints) {
  check_index(europe());
}
TEST_F(EuropeIndex, SummaryEqualsTheScan) {
  check_summaries(europe(), 1, 60);
}
TEST_F(EuropeIndex, QualityEqualsTheScan) {
  // The day has implausible values (SO6 glitches), so the comparison has something to compare.
  const QualityReport all = check_quality(europe(), {});
  EXPECT_GT(all.jumps.count + all.speed.count, 0u);
  check_quality_windows(europe());
}
TEST_F(EuropeIndex, QualityEventsUnderAQueryAreCheckQuality) {
  // quality_events() (what a store keeps to answer the quality block without the points), filtered here
  // by a filter written out plainly, against check_quality()'s own pass under the query.
  const TrailSet& set = europe();
  const auto events = quality_events(set);
  ASSERT_GT(events.size(), 0u);
  const auto& p = set.points();
  const double mid = std::floor((set.t_min() + set.t_max()) / 2);
  std::vector<Query> queries(6);
  queries[1].t0 = mid - 3 * 3600, queries[1].t1 = mid;
  queries[2].alt_min = 9000;
  queries[3].alt_max = 3000, queries[3].on_ground = false;
  queries[4].bbox = BBox{-5, 40, 10, 55};
  queries[5].callsign = {"A*"}, queries[5].alt_min = 1000, queries[5].alt_max = 12000;
  int nonempty = 0;
  for (const Query& q : queries) {
    auto passes = [&](std::uint32_t i) {
      const double a = p.alt[i], lat = p.lat[i], lon = p.lon[i];
      return (!q.t0 || p.t[i] >= *q.t0) && (!q.t1 || p.t[i] < *q.t1) && (!q.alt_min || a >= *q.alt_min) &&
             (!q.alt_max || a <= *q.alt_max) && (!(q.alt_min || q.alt_max) || !std::isnan(a)) &&
             (!q.on_ground || (p.on_ground[i] != 0) == *q.on_ground) &&
             (!q.bbox ||
              (lat >= q.bbox->south && lat <= q.bbox->north && lon >= q.bbox->west && lon <= q.bbox->east));
    };
    std::uint64_t n[3] = {0, 0, 0};
    std::vector<QualityExample> ex[3];
    for (const QualityEvent& e : events)
      if (q.matches_flight_ids(set.flights()[e.flight]) && passes(e.point) &&
          (e.kind != 2 || passes(e.point - 1))) {
        ++n[e.kind];
        ex[e.kind].push_back({e.flight, set.flights()[e.flight].callsign, p.t[e.point], e.value});
      }
    const QualityReport r = check_quality(set, q);
    const QualityCount* counts[3] = {&r.speed, &r.altitude, &r.jumps};
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(counts[k]->count, n[k]) << q.canonical() << " kind " << k;
      std::sort(ex[k].begin(), ex[k].end(), [](const QualityExample& a, const QualityExample& b) {
        return a.value != b.value ? a.value > b.value
                                  : (a.flight_id != b.flight_id ? a.flight_id < b.flight_id : a.t < b.t);
      });
      if (ex[k].size() > kQualityExamples) ex[k].resize(kQualityExamples);
      ASSERT_EQ(counts[k]->examples.size(), ex[k].size()) << q.canonical();
      for (std::size_t i = 0; i < ex[k].size(); ++i) {
        EXPECT_EQ(counts[k]->examples[i].flight_id, ex[k][i].flight_id);
        EXPECT_EQ(counts[k]->examples[i].t, ex[k][i].t);
        EXPECT_EQ(counts[k]->examples[i].value, ex[k][i].value);
      }
    }
    nonempty += n[0] + n[1] + n[2] > 0;
  }
  EXPECT_GE(nonempty, 4);
}
TEST_F(EuropeIndex, TilesEqualTheFullWalk) {
  check_tiles(europe(), {-10, 35, 30, 60});
}

TEST_F(FleetIndex, CountsMatchTheirPoints) {
  check_index(fleet());
}
TEST_F(FleetIndex, SummaryEqualsTheScan) {
  check_summaries(fleet(), 2, 80);
}
TEST_F(FleetIndex, QualityEqualsTheScan) {
  check_quality_windows(fleet());
}
TEST_F(FleetIndex, TilesEqualTheFullWalk) {
  check_tiles(fleet(), {-125, 24, -66, 50});
}

// Other filters take the scan; the index answers nothing it cannot.
TEST_F(FleetIndex, FilteredQueriesEqualTheScan) {
  const TrailSet& set = fleet();
  Query q;
  q.t0 = std::floor(set.t_min() / 3600) * 3600 + 7200, q.t1 = *q.t0 + 10 * 3600;
  q.alt_min = 3000;
  expect_same(summarize(set, q, {}), summarize_scan(set, q, {}), "alt band");
  q.alt_min.reset();
  q.callsign = "SWA";
  const Summary s = summarize(set, q, {});
  expect_same(s, summarize_scan(set, q, {}), "callsign");
  EXPECT_GT(s.points, 0u);
}

// A few points over a year: one bucket per kMinPointsPerBucket points at most (not kMaxBuckets of ~10 KiB
// each), and the summary of any window is still the scan's.
TEST(TimeIndex, SparseSetGetsFewWideBuckets) {
  constexpr std::size_t n = 3 * TimeIndex::kMinPointsPerBucket;
  PointColumns p;
  p.resize(n);
  const double year = 365.0 * 86400;
  for (std::size_t i = 0; i < n; ++i) {
    p.t[i] = 1.7e9 + year * static_cast<double>(i) / (n - 1);
    p.lat[i] = 50, p.lon[i] = 8 + 0.001 * static_cast<double>(i), p.alt[i] = 1000 + i, p.speed[i] = 200;
  }
  std::vector<Flight> f(1);
  f[0].begin = 0, f[0].end = n;
  compute_extents(f[0], p);
  const TrailSet set(p, f);
  const TimeIndex& ix = set.time_index();
  ASSERT_TRUE(ix.valid());
  // Three by the point count, one more where the buckets' alignment (origin a multiple of their width)
  // splits the span.
  EXPECT_LE(ix.buckets().size(), 4u);
  EXPECT_EQ(std::fmod(ix.bucket_seconds(), 600.0), 0.0);
  EXPECT_GE(ix.bucket_seconds() * static_cast<double>(ix.buckets().size()), year);
  EXPECT_LT(ix.bytes(), 64u * 1024);
  std::uint64_t total = 0;
  for (const auto& b : ix.buckets()) total += b.points;
  EXPECT_EQ(total, n);
  for (const double frac : {0.0, 0.2, 0.5}) {
    Query q;
    q.t0 = 1.7e9 + frac * year, q.t1 = 1.7e9 + (frac + 0.5) * year;
    expect_same(summarize(set, q, {}), summarize_scan(set, q, {}), "sparse");
  }
  expect_same(summarize(set, Query{}, {}), summarize_scan(set, Query{}, {}), "sparse, whole");
}

// A set whose flights are not in start order has no index, and the summary is the scan's.
TEST(TimeIndex, UnorderedFlightsHaveNone) {
  PointColumns p;
  p.resize(4);
  const double ts[] = {100, 110, 50, 60};
  for (int i = 0; i < 4; ++i) p.t[i] = ts[i], p.lat[i] = 1, p.lon[i] = 2 + i, p.alt[i] = 100, p.speed[i] = 50;
  std::vector<Flight> f(2);
  f[0].begin = 0, f[0].end = 2, f[1].begin = 2, f[1].end = 4;
  compute_extents(f[0], p), compute_extents(f[1], p);
  const TrailSet set(p, f);
  EXPECT_FALSE(set.time_index().valid());
  Query q;
  q.t0 = 55, q.t1 = 105;
  const Summary s = summarize(set, q, {});
  EXPECT_EQ(s.points, 2u);
  EXPECT_EQ(s.flights, 2u);
  std::swap(f[0], f[1]);
  const TrailSet ordered(p, f);
  EXPECT_TRUE(ordered.time_index().valid());
  expect_same(summarize(ordered, q, {}), summarize_scan(ordered, q, {}), "ordered");
  EXPECT_EQ(summarize(ordered, q, {}).points, 2u);
  // The flights without their points (the ClickHouse store's outline of a dataset): no index, and
  // nothing read past the empty columns.
  const TrailSet outline(PointColumns{}, ordered.flights());
  EXPECT_FALSE(outline.time_index().valid());
  EXPECT_EQ(outline.flights().size(), 2u);
}

}  // namespace
}  // namespace trailscope
