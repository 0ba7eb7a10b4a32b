#include "trailscope/trails/time_index.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <unordered_map>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "trailscope/trails/partial_reads.hpp"
#include "trailscope/trails/quality.hpp"
#include "trailscope/trails/summary.hpp"
#include "trailscope/trails/trail_set.hpp"

namespace trailscope {

namespace {

// The cell of t on a grid of `width` from `origin`: the b with origin + b·width <= t < origin + (b+1)·width,
// by exact comparisons (origin and width are whole seconds, so every edge is an exact double).
std::size_t cell_of(double t, double origin, double width, std::size_t cells) {
  auto b = static_cast<std::int64_t>(std::floor((t - origin) / width));
  while (b > 0 && t < origin + static_cast<double>(b) * width) --b;
  while (t >= origin + static_cast<double>(b + 1) * width) ++b;
  return static_cast<std::size_t>(std::clamp<std::int64_t>(b, 0, static_cast<std::int64_t>(cells) - 1));
}

// An upper bound of great_circle_m: a path along the meridian then along the parallel is no shorter than
// the great circle, and a parallel's arc is at most the equator's for the same Δlon. Cheap enough to rule
// out almost every step before the haversine.
double distance_bound_m(double lat_a, double lon_a, double lat_b, double lon_b) {
  constexpr double kRad = std::numbers::pi / 180.0;
  double dlon = std::fabs(lon_b - lon_a);
  if (dlon > 180) dlon = 360 - dlon;
  return kEarthMeanRadiusM * (std::fabs(lat_b - lat_a) + dlon) * kRad;
}

}  // namespace

TimeIndex::TimeIndex(const PointColumns& p, const std::vector<Flight>& flights) {
  if (flights.empty()) return;
  const std::size_t nf = flights.size();
  t_min_.resize(nf);
  run_max_.resize(nf);
  double run = -std::numeric_limits<double>::infinity(), lo = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < nf; ++i) {
    const Flight& f = flights[i];
    if (!std::isfinite(f.t_min) || !std::isfinite(f.t_max) || (i > 0 && f.t_min < flights[i - 1].t_min)) {
      *this = TimeIndex();
      return;  // not in start order (or a hand-made set with odd times): reads scan
    }
    if (f.begin > f.end || f.end > p.size()) {
      *this = TimeIndex();
      return;  // flights without their points (the ClickHouse store's outline of a dataset): nothing to index
    }
    t_min_[i] = f.t_min;
    run = std::max(run, f.t_max);
    run_max_[i] = run;
    lo = std::min(lo, f.t_min);
    crosses_ = crosses_ || f.crosses_antimeridian;
    if (!std::isnan(f.alt_max)) top_alt_m_ = std::max<double>(top_alt_m_, f.alt_max);
  }
  const double hi = run;

  // Buckets of 10 minutes (a multiple when the span is long: at most kMaxBuckets, and at most one per
  // kMinPointsPerBucket points), cells of a tenth of a bucket (a minute), both from a multiple of the
  // bucket width. The second bound keeps the index's cost in proportion to the points: every bucket holds
  // ~10 KiB of histograms per thread, so a few points spread over a year would otherwise cost 1,024 of them.
  const double tens = std::floor(hi / 600) - std::floor(lo / 600) + 1;
  const double most = std::clamp(std::floor(static_cast<double>(p.size()) / kMinPointsPerBucket), 1.0,
                                 static_cast<double>(kMaxBuckets));
  const double k = std::max(1.0, std::ceil(tens / most));
  bucket_s_ = 600 * k, fine_s_ = 60 * k;
  origin_ = std::floor(lo / bucket_s_) * bucket_s_;
  const auto nb = static_cast<std::size_t>(std::floor((hi - origin_) / bucket_s_)) + 1;
  const std::size_t cells_per_bucket = 10, ncell = nb * cells_per_bucket;

  // Altitude bins exactly as summarize() lays them out for this set, in both units.
  SummaryOptions ft, m;
  ft.alt_unit = AltUnit::ft, m.alt_unit = AltUnit::m;
  const SummaryLayout lft = summary_layout(Query{}, ft, lo, hi, top_alt_m_);
  const SummaryLayout lm = summary_layout(Query{}, m, lo, hi, top_alt_m_);

  struct Local {
    std::vector<Bucket> buckets;
    std::vector<std::uint32_t> fine;
    std::vector<Event> events;
    bool finite = true;
  };
  tbb::enumerable_thread_specific<Local> locals([&] {
    Local l;
    l.buckets.resize(nb);
    for (auto& b : l.buckets) {
      b.alt_ft.assign(lft.alt_bins, 0), b.alt_m.assign(lm.alt_bins, 0);
      b.speed.assign(SummaryLayout::kSpeedBins, 0);
      b.speed_min = std::numeric_limits<double>::infinity(), b.speed_max = -b.speed_min;
    }
    l.fine.assign(ncell, 0);
    return l;
  });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nf, 64), [&](const auto& r) {
    Local& L = locals.local();
    for (std::size_t fi = r.begin(); fi != r.end(); ++fi) {
      const Flight& f = flights[fi];
      double since = f.begin < f.end ? p.t[f.begin] : 0;
      for (std::size_t i = f.begin; i < f.end; ++i) {
        const double t = p.t[i];
        if (!std::isfinite(t)) {
          L.finite = false;
          return;
        }
        const std::size_t c = cell_of(t, origin_, fine_s_, ncell);
        ++L.fine[c];
        Bucket& b = L.buckets[c / cells_per_bucket];
        if (b.points++ == 0)
          b.t_first = b.t_last = t;
        else
          b.t_first = std::min(b.t_first, t), b.t_last = std::max(b.t_last, t);
        // The bins of summarize()'s scan (summary.cpp), point for point.
        const float a = p.alt[i];
        if (a == a) {
          const double af = a * lft.alt_scale + SummaryLayout::kAltEdgeNudge;
          ++b.alt_ft[af <= 0 ? 0 : std::min(static_cast<std::size_t>(af), lft.alt_bins - 1)];
          const double am = a * lm.alt_scale + SummaryLayout::kAltEdgeNudge;
          ++b.alt_m[am <= 0 ? 0 : std::min(static_cast<std::size_t>(am), lm.alt_bins - 1)];
        }
        const float v = p.speed[i];
        if (v == v) {
          ++b.speed_n, b.speed_sum += v;
          b.speed_min = std::min<double>(b.speed_min, v), b.speed_max = std::max<double>(b.speed_max, v);
          const float sb = v * static_cast<float>(1.0 / SummaryLayout::kSpeedBin);
          ++b.speed[sb <= 0
                        ? 0
                        : std::min<std::size_t>(static_cast<std::size_t>(sb), SummaryLayout::kSpeedBins - 1)];
        }
        // The implausible values of check_quality() (quality.cpp), with every point passing.
        const auto id = static_cast<std::uint32_t>(fi);
        if (p.speed[i] > kMaxPlausibleSpeedMs) L.events.push_back({t, t, p.speed[i], id, 0});
        if (p.alt[i] > kMaxPlausibleAltitudeM) L.events.push_back({t, t, p.alt[i], id, 1});
        if (i > f.begin) {
          const double dt = std::max(std::abs(t - since), kMinJumpSeconds);
          // 0.999: the haversine's own rounding never lifts a step past the bound.
          if (distance_bound_m(p.lat[i - 1], p.lon[i - 1], p.lat[i], p.lon[i]) / dt >
              0.999 * kMaxPlausibleSpeedMs) {
            const double v2 = implied_speed_ms(since, p.lat[i - 1], p.lon[i - 1], t, p.lat[i], p.lon[i]);
            if (v2 > kMaxPlausibleSpeedMs) L.events.push_back({t, p.t[i - 1], v2, id, 2});
          }
          if (p.lat[i] != p.lat[i - 1] || p.lon[i] != p.lon[i - 1]) since = t;
        }
      }
    }
  });

  // Merge the threads' parts.
  buckets_.resize(nb);
  for (auto& b : buckets_) {
    b.alt_ft.assign(lft.alt_bins, 0), b.alt_m.assign(lm.alt_bins, 0);
    b.speed.assign(SummaryLayout::kSpeedBins, 0);
    b.speed_min = std::numeric_limits<double>::infinity(), b.speed_max = -b.speed_min;
  }
  fine_.assign(ncell, 0);
  for (Local& L : locals) {
    if (!L.finite) {
      *this = TimeIndex();
      return;
    }
    for (std::size_t c = 0; c < ncell; ++c) fine_[c] += L.fine[c];
    for (std::size_t j = 0; j < nb; ++j) {
      Bucket &d = buckets_[j], &s = L.buckets[j];
      if (!s.points) continue;
      d.t_first = d.points ? std::min(d.t_first, s.t_first) : s.t_first;
      d.t_last = d.points ? std::max(d.t_last, s.t_last) : s.t_last;
      d.points += s.points;
      d.speed_n += s.speed_n, d.speed_sum += s.speed_sum;
      d.speed_min = std::min(d.speed_min, s.speed_min), d.speed_max = std::max(d.speed_max, s.speed_max);
      for (std::size_t i = 0; i < d.alt_ft.size(); ++i) d.alt_ft[i] += s.alt_ft[i];
      for (std::size_t i = 0; i < d.alt_m.size(); ++i) d.alt_m[i] += s.alt_m[i];
      for (std::size_t i = 0; i < d.speed.size(); ++i) d.speed[i] += s.speed[i];
    }
    events_.insert(events_.end(), L.events.begin(), L.events.end());
  }
  locals.clear();
  quality_indexed_ = static_cast<double>(events_.size()) <= kMaxEventFraction * static_cast<double>(p.size());
  if (quality_indexed_)
    std::sort(events_.begin(), events_.end(), [](const Event& a, const Event& b) {
      return a.t != b.t ? a.t < b.t : (a.flight != b.flight ? a.flight < b.flight : a.kind < b.kind);
    });
  else
    std::vector<Event>().swap(events_);

  // Callsign ids.
  std::unordered_map<std::string_view, std::uint32_t> ids;
  callsign_ids_.resize(nf);
  for (std::size_t i = 0; i < nf; ++i) {
    const auto [it, added] =
        ids.try_emplace(flights[i].callsign, static_cast<std::uint32_t>(callsign_names_.size()));
    if (added) callsign_names_.push_back(flights[i].callsign);
    callsign_ids_[i] = it->second;
  }
  valid_ = true;
}

std::pair<std::size_t, std::size_t> TimeIndex::flight_range(double t0, double t1) const {
  // Flights with t_min >= t1 or t_max < t0 cannot meet [t0, t1): the first are a suffix (start order),
  // the second include every flight before the first whose running maximum of t_max reaches t0.
  const std::size_t last =
      static_cast<std::size_t>(std::lower_bound(t_min_.begin(), t_min_.end(), t1) - t_min_.begin());
  const std::size_t first =
      static_cast<std::size_t>(std::lower_bound(run_max_.begin(), run_max_.end(), t0) - run_max_.begin());
  return {std::min(first, last), last};
}

std::size_t TimeIndex::bytes() const {
  std::size_t n = sizeof(*this) + (t_min_.size() + run_max_.size()) * sizeof(double) +
                  fine_.size() * sizeof(std::uint32_t) + events_.size() * sizeof(Event) +
                  callsign_ids_.size() * sizeof(std::uint32_t);
  for (const Bucket& b : buckets_)
    n += sizeof(Bucket) + (b.alt_ft.size() + b.alt_m.size()) * 8 + b.speed.size() * 4;
  for (const auto& s : callsign_names_) n += sizeof(std::string) + s.capacity();
  return n;
}

}  // namespace trailscope
