#include "trailscope/trails/quality.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include "trailscope/trails/point_filter.hpp"
#include "trailscope/trails/time_index.hpp"

namespace trailscope {

double great_circle_m(double lat1, double lon1, double lat2, double lon2) {
  constexpr double kRad = std::numbers::pi / 180.0;
  const double dlat = (lat2 - lat1) * kRad, dlon = (lon2 - lon1) * kRad;
  const double s = std::sin(dlat / 2), c = std::sin(dlon / 2);
  const double h = s * s + std::cos(lat1 * kRad) * std::cos(lat2 * kRad) * c * c;
  return 2 * kEarthMeanRadiusM * std::asin(std::min(1.0, std::sqrt(h)));
}

double implied_speed_ms(double t_a, double lat_a, double lon_a, double t_b, double lat_b, double lon_b) {
  return great_circle_m(lat_a, lon_a, lat_b, lon_b) / std::max(std::abs(t_b - t_a), kMinJumpSeconds);
}

void keep_largest_examples(std::vector<QualityExample>& e) {
  const auto by = [](const QualityExample& a, const QualityExample& b) {
    return a.value != b.value ? a.value > b.value
                              : (a.flight_id != b.flight_id ? a.flight_id < b.flight_id : a.t < b.t);
  };
  if (e.size() > kQualityExamples) {
    std::partial_sort(e.begin(), e.begin() + kQualityExamples, e.end(), by);
    e.resize(kQualityExamples);
  } else {
    std::sort(e.begin(), e.end(), by);
  }
}

namespace {
// Counts and every candidate example of one range of flights; examples are cut to the largest at the end.
struct Acc {
  std::uint64_t n[3] = {0, 0, 0};
  std::vector<QualityExample> ex[3];
  void add(int kind, std::uint32_t id, double t, double v) {
    ++n[kind];
    ex[kind].push_back({id, {}, t, v});
  }
  // Keeps the kQualityExamples largest, so the merge stays small.
  void trim() {
    for (auto& e : ex) keep_largest_examples(e);
  }
};

nlohmann::json count_json(const QualityCount& c, const char* extra, double scale) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& e : c.examples)
    list.push_back({{"flight_id", e.flight_id},
                    {"callsign", e.callsign},
                    {"t", e.t},
                    {"value", e.value},
                    {extra, e.value / scale}});
  return {{"count", c.count}, {"examples", std::move(list)}};
}
}  // namespace

namespace {
// The implausible values of one flight among its samples that `pass`: emit(kind, index, value) for each.
// Jumps are timed from the first report of the previous sample's position, whether it passes or not.
template <class Pass, class Emit>
void flight_quality(const PointColumns& p, const Flight& f, const Pass& pass, Emit&& emit) {
  if (f.begin >= f.end) return;
  bool prev = false;
  double since = p.t[f.begin];  // first report of the previous sample's position
  for (std::size_t i = f.begin; i < f.end; ++i) {
    const bool ok = pass(i);
    if (ok) {
      if (p.speed[i] > kMaxPlausibleSpeedMs) emit(0, i, p.speed[i]);
      if (p.alt[i] > kMaxPlausibleAltitudeM) emit(1, i, p.alt[i]);
      if (prev) {
        const double v = implied_speed_ms(since, p.lat[i - 1], p.lon[i - 1], p.t[i], p.lat[i], p.lon[i]);
        if (v > kMaxPlausibleSpeedMs) emit(2, i, v);
      }
    }
    prev = ok;
    if (i > f.begin && (p.lat[i] != p.lat[i - 1] || p.lon[i] != p.lon[i - 1])) since = p.t[i];
  }
}
}  // namespace

QualityReport check_quality(const TrailSet& set, const Query& q) {
  const auto& p = set.points();
  const auto& flights = set.flights();
  const PointFilter filter(q);
  Acc total = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, flights.size(), 64), Acc{},
      [&](const tbb::blocked_range<std::size_t>& r, Acc acc) {
        for (std::size_t fi = r.begin(); fi != r.end(); ++fi) {
          const Flight& f = flights[fi];
          if (!q.may_match(f)) continue;
          const auto id = static_cast<std::uint32_t>(fi);
          flight_quality(
              p, f, [&](std::size_t i) { return filter(p, i); },
              [&](int kind, std::size_t i, double v) { acc.add(kind, id, p.t[i], v); });
        }
        acc.trim();
        return acc;
      },
      [](Acc a, const Acc& b) {
        for (int k = 0; k < 3; ++k) {
          a.n[k] += b.n[k];
          a.ex[k].insert(a.ex[k].end(), b.ex[k].begin(), b.ex[k].end());
        }
        a.trim();
        return a;
      });
  QualityReport out;
  QualityCount* counts[3] = {&out.speed, &out.altitude, &out.jumps};
  for (int k = 0; k < 3; ++k) {
    counts[k]->count = total.n[k];
    counts[k]->examples = std::move(total.ex[k]);
    for (auto& e : counts[k]->examples) e.callsign = flights[e.flight_id].callsign;
  }
  return out;
}

std::vector<QualityEvent> quality_events(const TrailSet& set) {
  const auto& p = set.points();
  const auto& flights = set.flights();
  using Events = std::vector<QualityEvent>;
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, flights.size(), 64), Events{},
      [&](const tbb::blocked_range<std::size_t>& r, Events acc) {
        for (std::size_t fi = r.begin(); fi != r.end(); ++fi)
          flight_quality(
              p, flights[fi], [](std::size_t) { return true; },
              [&](int kind, std::size_t i, double v) {
                acc.push_back({static_cast<std::uint32_t>(fi), static_cast<std::uint32_t>(i),
                               static_cast<std::uint8_t>(kind), v});
              });
        return acc;
      },
      [](Events a, const Events& b) {  // left before right: flight order
        a.insert(a.end(), b.begin(), b.end());
        return a;
      });
}

QualityReport window_quality(const TrailSet& set, double t0, double t1) {
  const TimeIndex& ix = set.time_index();
  if (!ix.valid() || !ix.quality_indexed()) {
    Query q;
    if (t0 > -std::numeric_limits<double>::infinity()) q.t0 = t0;
    if (t1 < std::numeric_limits<double>::infinity()) q.t1 = t1;
    return check_quality(set, q);
  }
  const auto& ev = ix.events();
  const auto by_t = [](const TimeIndex::Event& e, double t) { return e.t < t; };
  const auto first = std::lower_bound(ev.begin(), ev.end(), t0, by_t);
  const auto last = std::lower_bound(first, ev.end(), t1, by_t);
  Acc acc;
  // Both samples of a jump must pass the window, as in check_quality().
  for (auto it = first; it != last; ++it)
    if (it->kind != 2 || (it->t_prev >= t0 && it->t_prev < t1))
      acc.add(it->kind, it->flight, it->t, it->value);
  acc.trim();
  QualityReport out;
  QualityCount* counts[3] = {&out.speed, &out.altitude, &out.jumps};
  for (int k = 0; k < 3; ++k) {
    counts[k]->count = acc.n[k];
    counts[k]->examples = std::move(acc.ex[k]);
    for (auto& e : counts[k]->examples) e.callsign = set.flights()[e.flight_id].callsign;
  }
  return out;
}

nlohmann::json QualityReport::to_json() const {
  return {{"limits",
           {{"speed_ms", kMaxPlausibleSpeedMs},
            {"speed_kt", kMaxPlausibleSpeedMs / kKnot},
            {"altitude_m", kMaxPlausibleAltitudeM},
            {"altitude_fl", kMaxPlausibleAltitudeM / 0.3048 / 100}}},
          {"speed", count_json(speed, "value_kt", kKnot)},
          {"altitude", count_json(altitude, "value_fl", 0.3048 * 100)},
          {"jumps", count_json(jumps, "value_kt", kKnot)}};
}

}  // namespace trailscope
