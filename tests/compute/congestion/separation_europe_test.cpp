// Losses of separation over the real Europe SO6 day (11,043 flights), against a brute force written here
// that shares no code with separation.cpp: every 2 s, the positions of all flights from positions_at
// (trails/), every pair within 0.1° of latitude compared by GeographicLib's geodesic distance (no hash,
// no tangent plane, no exact solve). With a tolerance of 5 m horizontally (the tangent plane's documented
// error is below 3 m) and 1 cm vertically:
//   (a) every sampled instant where a pair is certainly infringing (< 5 NM - 5 m and < minimum - 1 cm)
//       lies inside an event of that pair;
//   (b) every sampled instant inside an event is at least nearly infringing for the brute force
//       (< 5 NM + 5 m and < minimum + 1 cm), and every event's CPA agrees with the geodesic distance
//       between positions_at's positions of the two flights at cpa_t within 3 m;
// so both find the same pairs and the same events, up to encounters shorter than the 2 s step (checked
// at their CPA only) and to grazing ones within the tolerance.
#include <GeographicLib/Geodesic.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <mutex>
#include <set>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include "test_support.hpp"
#include "trailscope/congestion/separation.hpp"
#include "trailscope/ingest/ingest.hpp"
#include "trailscope/trails/positions.hpp"

namespace trailscope::congestion {
namespace {

constexpr double kStep = 2.0;
constexpr double kTolH = 5.0, kTolV = 0.01;

std::filesystem::path so6_path() {
  return test::shared_data("flights/traffic_europe_20180101_m3.so6.gz");
}

std::uint64_t key(std::uint32_t a, std::uint32_t b) {
  return static_cast<std::uint64_t>(std::min(a, b)) << 32 | std::max(a, b);
}

TEST(SeparationEurope, SameEventsAsDenseGeodesicSampling) {
  if (!std::filesystem::exists(so6_path())) GTEST_SKIP() << so6_path() << " is absent";
  ingest::IngestReport rep;
  const TrailSet set = ingest::ingest_file(so6_path().string(), {}, &rep);
  // 11,043 flight ids, split by default between two legs and at teleports.
  ASSERT_EQ(set.num_flights(), 11043u + rep.leg_splits.count + rep.jump_splits.count);
  const SeparationMinima m;
  const double t0 = std::floor(set.t_min()), t1 = std::floor(set.t_max()) + 1;
  Query q;
  q.t0 = t0, q.t1 = t1;
  const SeparationResult r = losses_of_separation(set, q, m);
  ASSERT_GT(r.events.size(), 100u);
  EXPECT_EQ(r.flights, set.num_flights());

  // Events of a pair are disjoint and ordered.
  std::map<std::uint64_t, std::vector<const SeparationEvent*>> by_pair;
  for (const SeparationEvent& e : r.events) {
    ASSERT_LT(e.flight_a, e.flight_b);
    ASSERT_LT(e.t_start, e.t_end);
    by_pair[key(e.flight_a, e.flight_b)].push_back(&e);
  }
  for (auto& [k, v] : by_pair) {
    std::sort(v.begin(), v.end(), [](auto* x, auto* y) { return x->t_start < y->t_start; });
    for (std::size_t i = 1; i < v.size(); ++i) EXPECT_GT(v[i]->t_start, v[i - 1]->t_end);
  }
  EXPECT_EQ(by_pair.size(), r.pairs_with_events);

  // The brute force: (pair, step index) where certainly / nearly infringing.
  const auto& g = GeographicLib::Geodesic::WGS84();
  const std::size_t n_steps = static_cast<std::size_t>((t1 - t0) / kStep);
  std::vector<std::vector<std::uint64_t>> certain(n_steps), near(n_steps);
  const double lat_reach = 0.1;  // > 5 NM / a(1 - e²) in degrees (0.0837°)
  tbb::parallel_for(std::size_t{0}, n_steps, [&](std::size_t k) {
    const double t = t0 + kStep * static_cast<double>(k);
    std::vector<Position> p = positions_at(set, t, Query{}, 1'000'000).positions;
    std::erase_if(p, [](const Position& x) { return x.on_ground || std::isnan(x.alt_m); });
    std::sort(p.begin(), p.end(), [](const Position& x, const Position& y) { return x.lat < y.lat; });
    for (std::size_t i = 0; i < p.size(); ++i)
      for (std::size_t j = i + 1; j < p.size() && p[j].lat - p[i].lat < lat_reach; ++j) {
        const double dlon = std::fabs(std::remainder(p[j].lon - p[i].lon, 360.0));
        if (dlon * std::cos(std::max(std::fabs(p[i].lat), std::fabs(p[j].lat)) * M_PI / 180) > 0.2) continue;
        const bool high = p[i].alt_m > m.high_above_m || p[j].alt_m > m.high_above_m;
        const double v = high ? m.vertical_high_m : m.vertical_m;
        const double dz = std::fabs(p[i].alt_m - p[j].alt_m);
        if (dz >= v + kTolV) continue;
        double d = 0;
        g.Inverse(p[i].lat, p[i].lon, p[j].lat, p[j].lon, d);
        if (d >= m.horizontal_m + kTolH) continue;
        // Two flights that share a single instant (one lands as the other takes off, at the same sample
        // time) have no encounter of positive length.
        const Flight& fi = set.flights()[p[i].flight_id];
        const Flight& fj = set.flights()[p[j].flight_id];
        if (std::max(fi.t_min, fj.t_min) >= std::min(fi.t_max, fj.t_max)) continue;
        const std::uint64_t kk = key(p[i].flight_id, p[j].flight_id);
        near[k].push_back(kk);
        if (d < m.horizontal_m - kTolH && dz < v - kTolV) certain[k].push_back(kk);
      }
    std::sort(near[k].begin(), near[k].end());
  });

  // (a) certain ⇒ inside an event of the pair.
  std::size_t n_certain = 0, missed = 0;
  std::set<std::uint64_t> certain_pairs;
  for (std::size_t k = 0; k < n_steps; ++k)
    for (const std::uint64_t kk : certain[k]) {
      ++n_certain;
      certain_pairs.insert(kk);
      const double t = t0 + kStep * static_cast<double>(k);
      const auto it = by_pair.find(kk);
      bool inside = false;
      if (it != by_pair.end())
        for (const SeparationEvent* e : it->second) inside = inside || (e->t_start <= t && t <= e->t_end);
      if (!inside && ++missed <= 10)
        ADD_FAILURE() << "pair " << (kk >> 32) << "," << (kk & 0xffffffffu) << " infringes at t=" << t
                      << " but no event holds it";
    }
  EXPECT_EQ(missed, 0u);
  EXPECT_GT(n_certain, 1000u);

  // (b) inside an event ⇒ nearly infringing at every sampled instant; CPA against the geodesic.
  std::size_t checked = 0, wrong = 0;
  for (const SeparationEvent& e : r.events) {
    const std::uint64_t kk = key(e.flight_a, e.flight_b);
    const auto k_lo = static_cast<std::size_t>(std::ceil((e.t_start - t0) / kStep));
    for (std::size_t k = k_lo; k < n_steps && t0 + kStep * static_cast<double>(k) <= e.t_end; ++k) {
      const double t = t0 + kStep * static_cast<double>(k);
      if (t <= e.t_start + 1e-6 || t >= e.t_end - 1e-6) continue;
      ++checked;
      if (!std::binary_search(near[k].begin(), near[k].end(), kk) && ++wrong <= 10)
        ADD_FAILURE() << "event " << e.flight_a << "," << e.flight_b << " [" << e.t_start << ", " << e.t_end
                      << "] holds t=" << t << " where the pair is separated";
    }
    const Positions p = positions_at(set, e.cpa_t, Query{}, 1'000'000);
    const Position *a = nullptr, *b = nullptr;
    for (const Position& x : p.positions) {
      if (x.flight_id == e.flight_a) a = &x;
      if (x.flight_id == e.flight_b) b = &x;
    }
    ASSERT_TRUE(a && b);
    double d = 0;
    g.Inverse(a->lat, a->lon, b->lat, b->lon, d);
    EXPECT_NEAR(d, e.cpa_horizontal_m, 3.0);
    EXPECT_LT(d, m.horizontal_m + 3.0);
    EXPECT_NEAR(std::fabs(a->alt_m - b->alt_m), e.cpa_vertical_m, 1e-3);
    EXPECT_NEAR(a->lat, e.cpa_lat_a, 1e-9);
    EXPECT_NEAR(b->lon, e.cpa_lon_b, 1e-9);
  }
  EXPECT_EQ(wrong, 0u);
  EXPECT_GT(checked, 1000u);
  // Every pair the brute force certainly saw is a pair with events (by (a)), and most event pairs were
  // seen by the brute force: the rest are shorter than the step or graze the minimum.
  std::size_t seen = 0;
  for (const auto& [kk, v] : by_pair) seen += certain_pairs.count(kk);
  EXPECT_EQ(seen, certain_pairs.size());
  EXPECT_GT(static_cast<double>(seen), 0.9 * static_cast<double>(by_pair.size()));
  RecordProperty("events", std::to_string(r.events.size()));
  RecordProperty("pairs", std::to_string(by_pair.size()));
  RecordProperty("pairs_seen_by_sampling", std::to_string(seen));
}

}  // namespace
}  // namespace trailscope::congestion
