#include "trailscope/congestion/separation.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/core/text.hpp"
#include "intervals.hpp"

namespace trailscope::congestion {

namespace {

using namespace detail;

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
// WGS84 (NIMA TR8350.2, 2000).
constexpr double kA = 6378137.0;
constexpr double kF = 1.0 / 298.257223563;
constexpr double kE2 = kF * (2.0 - kF);
// The least radii of curvature: M(φ) >= a(1 - e²) (at the equator), N(φ) >= a.
constexpr double kMinMeridional = kA * (1.0 - kE2);
constexpr double kInf = std::numeric_limits<double>::infinity();
// Hash cells, degrees.
constexpr double kCellDeg = 0.5;
constexpr int kLatCells = static_cast<int>(180.0 / kCellDeg);
constexpr int kLonCells = static_cast<int>(360.0 / kCellDeg);
// Buckets per progress report / cancellation check.
constexpr std::size_t kBucketsPerChunk = 32;

double meridional_radius(double phi) {
  const double s = std::sin(phi);
  const double w = 1.0 - kE2 * s * s;
  return kA * (1.0 - kE2) / (w * std::sqrt(w));
}
double normal_radius(double phi) {
  const double s = std::sin(phi);
  return kA / std::sqrt(1.0 - kE2 * s * s);
}

// One aircraft on one segment, over a piece starting at time s: values at s and slopes per second.
struct Lin {
  double lat, lon, alt;     // at s; lon unwrapped along the segment (may leave [-180, 180))
  double klat, klon, kalt;  // per second
  double lat_at(double dt) const { return lat + klat * dt; }
  double lon_at(double dt) const { return lon + klon * dt; }
  double alt_at(double dt) const { return alt + kalt * dt; }
};

Lin on_segment(const PointColumns& p, std::uint32_t i, double s) {
  const double dt = p.t[i + 1] - p.t[i];
  const double w = (s - p.t[i]) / dt;
  Lin l;
  const double dlat = static_cast<double>(p.lat[i + 1]) - p.lat[i];
  const double dlon = lon_step(p.lon[i], p.lon[i + 1]);
  const double dalt = static_cast<double>(p.alt[i + 1]) - p.alt[i];
  l.lat = p.lat[i] + dlat * w, l.lon = p.lon[i] + dlon * w, l.alt = p.alt[i] + dalt * w;
  l.klat = dlat / dt, l.klon = dlon / dt, l.kalt = dalt / dt;
  return l;
}

bool airborne(const PointColumns& p, std::uint32_t i) {
  return p.on_ground[i] == 0 && p.on_ground[i + 1] == 0 && !std::isnan(p.alt[i]) && !std::isnan(p.alt[i + 1]);
}

// One flight's airborne trajectory within one bucket: its box (degrees, metres), lon unwrapped so that
// lon_lo is in [-180, 180).
struct Entry {
  std::uint32_t bucket;
  std::uint32_t flight;
  float lat_lo, lat_hi, alt_lo, alt_hi;
  double lon_lo, lon_hi;
};

// A part of a pair's time line within one bucket: an infringement (strict) or a stretch where the pair is
// within the vertical minimum and the window's filters and at most kJoinToleranceM beyond the horizontal
// minimum (relaxed), which joins the infringements on either side of it into one event.
struct Part {
  std::uint32_t a, b;  // flight ids, a < b
  double start, end;
  bool strict;
  double cpa_t, cpa_h, cpa_v, min_v;   // strict parts only
  std::uint32_t cpa_seg_a, cpa_seg_b;  // segments holding cpa_t
};

struct Context {
  const TrailSet& set;
  const Query& q;
  const SeparationMinima& m;
  double t0, t1;
  double v_max;
  bool has_band;
  double band_lo, band_hi;
};

double min_abs(double v0, double v1) {
  return (v0 <= 0 && v1 >= 0) || (v0 >= 0 && v1 <= 0) ? 0.0 : std::min(std::fabs(v0), std::fabs(v1));
}

// Where a·x² + 2b·x + c < r² on [0, len] (a >= 0: convex, so one interval).
Iv below(double a, double b, double c, double r, double len) {
  const double cc = c - r * r;
  if (a == 0) return cc < 0 ? Iv{0, len} : Iv{0, 0};
  const double disc = b * b - a * cc;
  if (!(disc > 0)) return {0, 0};
  // Stable roots (Press et al., Numerical Recipes, 3rd ed., 2007, §5.6).
  const double qq = -(b + std::copysign(std::sqrt(disc), b));
  double r1 = qq / a, r2 = qq != 0 ? cc / qq : -r1;
  if (r1 > r2) std::swap(r1, r2);
  return {std::max(r1, 0.0), std::min(r2, len)};
}

// The exact solve over [lo, hi] for flights a and b: appends the parts of their time line, joining
// contiguous parts of the same kind.
void solve_pair(const Context& c, std::uint32_t fa, std::uint32_t fb, double lo, double hi,
                std::vector<Part>& out) {
  const PointColumns& p = c.set.points();
  const Flight& A = c.set.flights()[fa];
  const Flight& B = c.set.flights()[fb];
  lo = std::max({lo, A.t_min, B.t_min});
  hi = std::min({hi, A.t_max, B.t_max});
  if (!(hi > lo)) return;
  const double* ta = p.t.data();
  // Segment i holds [t[i], t[i+1]] with t[i] <= lo < t[i+1].
  std::uint32_t ia = static_cast<std::uint32_t>(std::upper_bound(ta + A.begin, ta + A.end, lo) - ta) - 1;
  std::uint32_t ib = static_cast<std::uint32_t>(std::upper_bound(ta + B.begin, ta + B.end, lo) - ta) - 1;
  const double H = c.m.horizontal_m, HR = H + kJoinToleranceM;
  const std::size_t first_out = out.size();
  // Scratch reused across calls (this runs hundreds of thousands of times per day of traffic).
  thread_local std::vector<double> cuts;
  thread_local std::vector<Iv> relaxed, strict;

  const auto emit = [&](const Part& part) {
    if (!(part.end > part.start)) return;
    if (out.size() > first_out) {
      Part& last = out.back();
      if (last.end == part.start && last.strict == part.strict) {
        last.end = part.end;
        if (part.strict) {
          if (part.cpa_h < last.cpa_h)
            last.cpa_t = part.cpa_t, last.cpa_h = part.cpa_h, last.cpa_v = part.cpa_v,
            last.cpa_seg_a = part.cpa_seg_a, last.cpa_seg_b = part.cpa_seg_b;
          last.min_v = std::min(last.min_v, part.min_v);
        }
        return;
      }
    }
    out.push_back(part);
  };

  double s = lo;
  while (s < hi) {
    const double e = std::min({p.t[ia + 1], p.t[ib + 1], hi});
    if (e > s && airborne(p, ia) && airborne(p, ib)) {
      const Lin la = on_segment(p, ia, s), lb = on_segment(p, ib, s);
      const double len = e - s;
      // Coarse rejection on the whole piece, with bounds that only under-estimate the distance.
      const double dlat0 = lb.lat - la.lat, dlat1 = lb.lat_at(len) - la.lat_at(len);
      double dlon0 = lb.lon - la.lon, dlon1 = lb.lon_at(len) - la.lon_at(len);
      const double shift = wrap_lon(0.5 * (dlon0 + dlon1)) - 0.5 * (dlon0 + dlon1);
      dlon0 += shift, dlon1 += shift;
      const double dz0 = lb.alt - la.alt, dz1 = lb.alt_at(len) - la.alt_at(len);
      const double max_lat = std::max(
          {std::fabs(la.lat), std::fabs(la.lat_at(len)), std::fabs(lb.lat), std::fabs(lb.lat_at(len))});
      const double cos_max = std::cos(std::min(max_lat * kDeg, kPi / 2));
      const bool far = min_abs(dlat0, dlat1) * kDeg * kMinMeridional >= HR ||
                       min_abs(dlon0, dlon1) * kDeg * kA * cos_max >= HR || min_abs(dz0, dz1) >= c.v_max;
      if (!far) {
        // Sub-pieces: FL410 crossings of either aircraft, and latitude steps of kSubPieceLatDeg.
        cuts.assign({0.0, len});
        for (const Lin* l : {&la, &lb}) {
          if (l->kalt != 0) {
            const double tc = (c.m.high_above_m - l->alt) / l->kalt;
            if (tc > 0 && tc < len) cuts.push_back(tc);
          }
        }
        const double dlat_max = std::max(std::fabs(la.klat), std::fabs(lb.klat)) * len;
        const int n = static_cast<int>(std::min(1e6, std::ceil(dlat_max / kSubPieceLatDeg)));
        for (int k = 1; k < n; ++k) cuts.push_back(len * k / n);
        std::sort(cuts.begin(), cuts.end());
        cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
        for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
          // Sub-piece [u, v] in piece time; its ends are the same doubles for both neighbours.
          const double u = cuts[k], v = cuts[k + 1], sl = v - u;
          const double mid = 0.5 * (u + v);
          const double phi0 = 0.5 * (la.lat_at(mid) + lb.lat_at(mid)) * kDeg;
          const double sx = normal_radius(phi0) * std::cos(phi0) * kDeg, sy = meridional_radius(phi0) * kDeg;
          const double X0 = (lb.lon_at(u) - la.lon_at(u) + shift) * sx, Xv = (lb.klon - la.klon) * sx;
          const double Y0 = (lb.lat_at(u) - la.lat_at(u)) * sy, Yv = (lb.klat - la.klat) * sy;
          const double Z0 = lb.alt_at(u) - la.alt_at(u), Zv = lb.kalt - la.kalt;
          const bool high = la.alt_at(mid) > c.m.high_above_m || lb.alt_at(mid) > c.m.high_above_m;
          const double V = high ? c.m.vertical_high_m : c.m.vertical_m;
          // Horizontal² = qa·x² + 2qb·x + qc, x = t - (s + u).
          const double qa = Xv * Xv + Yv * Yv, qb = X0 * Xv + Y0 * Yv, qc = X0 * X0 + Y0 * Y0;
          const Iv hor_relaxed = below(qa, qb, qc, HR, sl);
          if (!(hor_relaxed.hi > hor_relaxed.lo)) continue;
          relaxed.assign({hor_relaxed});
          // Vertical: |Z0 + Zv·x| < V.
          intersect(relaxed, linear_within(Z0, Zv, -V, V, sl));
          // The window's altitude band and bbox, for both aircraft.
          for (const Lin* l : {&la, &lb}) {
            if (relaxed.empty()) break;
            if (c.has_band)
              intersect(relaxed, linear_within(l->alt_at(u), l->kalt, c.band_lo, c.band_hi, sl));
            if (c.q.bbox)
              intersect_bbox(relaxed, l->lat_at(u), l->klat, l->lon_at(u), l->klon, *c.q.bbox, sl);
          }
          if (relaxed.empty()) continue;
          // The strict parts lie inside the relaxed ones by construction (same list, narrower horizontal).
          strict = relaxed;
          intersect(strict, below(qa, qb, qc, H, sl));
          // Absolute times: the sub-piece's own ends where an interval reaches them, so neighbours join.
          const auto at = [&](double x) {
            if (x <= 0) return u == 0 ? s : s + u;
            if (x >= sl) return v == len ? e : s + v;
            return s + u + x;
          };
          std::size_t j = 0;
          for (const Iv& r : relaxed) {
            double cur = r.lo;
            for (; j < strict.size() && strict[j].lo < r.hi; ++j) {
              const Iv& iv = strict[j];
              emit({fa, fb, at(cur), at(iv.lo), false, 0, 0, 0, 0, 0, 0});
              // CPA on [iv.lo, iv.hi]: the vertex of the parabola clamped; the earliest instant when flat.
              const double x = qa > 0 ? std::clamp(-qb / qa, iv.lo, iv.hi) : iv.lo;
              const double h = std::hypot(X0 + Xv * x, Y0 + Yv * x);
              const double min_v = min_abs(Z0 + Zv * iv.lo, Z0 + Zv * iv.hi);
              emit({fa, fb, at(iv.lo), at(iv.hi), true, s + u + x, h, std::fabs(Z0 + Zv * x), min_v, ia, ib});
              cur = iv.hi;
            }
            emit({fa, fb, at(cur), at(r.hi), false, 0, 0, 0, 0, 0, 0});
          }
        }
      }
    }
    if (p.t[ia + 1] == e) ++ia;
    if (p.t[ib + 1] == e) ++ib;
    s = e;
    if (ia + 1 >= A.end || ib + 1 >= B.end) break;
  }
}

}  // namespace

SeparationResult losses_of_separation(const TrailSet& set, const Query& q, const SeparationMinima& m,
                                      const ProgressFn& progress, const CancelToken* cancel) {
  if (!q.t0) throw invalid_argument("t0", "t0: separation needs a time window; give t0 and t1");
  if (!q.t1) throw invalid_argument("t1", "t1: separation needs a time window; give t0 and t1");
  const double t0 = *q.t0, t1 = *q.t1;
  if (!std::isfinite(t0)) throw invalid_argument("t0", "t0: must be a finite time");
  if (!std::isfinite(t1) || !(t1 > t0)) throw invalid_argument("t1", "t1: must be a finite time after t0");
  if (t1 - t0 > limits::kMaxQuerySpanSeconds)
    throw invalid_argument(
        "t1", "t1: the window t1 - t0 is longer than " + format_double(limits::kMaxQuerySpanSeconds) + " s");
  if (q.on_ground && *q.on_ground)
    throw invalid_argument("on_ground",
                           "on_ground=true: separation is between airborne aircraft; leave on_ground out");
  const auto positive = [](double v, const char* name) {
    if (!(std::isfinite(v) && v > 0))
      throw invalid_argument(name, std::string(name) + ": must be a finite distance > 0 (metres)");
  };
  positive(m.horizontal_m, "horizontal_m");
  positive(m.vertical_m, "vertical_m");
  positive(m.vertical_high_m, "vertical_high_m");
  if (m.vertical_high_m < m.vertical_m)
    throw invalid_argument("vertical_high_m", "vertical_high_m: must be >= vertical_m");
  if (!std::isfinite(m.high_above_m))
    throw invalid_argument("high_above_m", "high_above_m: must be a finite altitude (metres)");

  Context c{set,
            q,
            m,
            t0,
            t1,
            std::max(m.vertical_m, m.vertical_high_m),
            q.alt_min || q.alt_max,
            q.alt_min.value_or(-kInf),
            q.alt_max.value_or(kInf)};
  const PointColumns& p = set.points();
  const auto& flights = set.flights();

  SeparationResult res;
  res.t0 = t0, res.t1 = t1, res.minima = m;

  // Buckets [t0 + k·B, t0 + (k+1)·B) ∩ [t0, t1); the bounds are computed by one expression so that a
  // pair's intervals in neighbouring buckets meet at the same double.
  const double span = t1 - t0;
  const std::size_t n_buckets = static_cast<std::size_t>(std::ceil(span / kBucketSeconds));
  const auto bucket_lo = [&](std::size_t k) { return k == 0 ? t0 : std::min(t1, t0 + k * kBucketSeconds); };

  std::vector<std::uint32_t> selected;
  for (std::uint32_t f = 0; f < flights.size(); ++f)
    if (flights[f].size() >= 2 && q.may_match(flights[f])) selected.push_back(f);
  res.flights = selected.size();

  // ---- 1. boxes per flight and bucket ------------------------------------------------------------------
  // Why the hash never misses a pair. Let H' = horizontal_m + kJoinToleranceM (the solve looks for
  // strict parts below H and for the relaxed parts that join them below H'). Say a and b are within H' at
  // an instant t of bucket k. The solve measures dy = M(φ0)·Δφ(t) and dx = N(φ0)·cos(φ0)·Δλ(t), with φ0
  // the pair's mean latitude at the middle of a sub-piece; sub-pieces lie within one bucket (the solve
  // runs per bucket), so each aircraft's latitude at that middle instant is inside its own box of bucket
  // k, and |φ0| <= max(Φa, Φb) with Φ the largest |latitude| of a box. From horizontal < H':
  // |Δφ(t)| < H' / M(φ0) <= H' / (a(1-e²)) and |Δλ(t)| < H' / (N(φ0)·cos φ0) <= H' / (a·cos(max(Φa, Φb)))
  // = max(ha, hb) with h = H' / (a·cos Φ). Both positions at t lie in their boxes, so the boxes are closer
  // than those bounds in latitude and in longitude (the short way). Each box is grown by
  // H' / (a(1-e²)) / 2 in latitude and by its own h in longitude (h_a + h_b >= max(ha, hb)): the grown
  // boxes overlap, and the overlap lies in some cell both were inserted into (cells wrap at 180°). The
  // altitude ranges overlap once grown by half the larger vertical minimum each. Growth is further
  // scaled by kSafety, and float bounds rounded outwards, against rounding.
  constexpr double kSafety = 1.001;
  const double h_reach = m.horizontal_m + kJoinToleranceM;
  const double lat_grow = kSafety * 0.5 * h_reach / kMinMeridional / kDeg;
  std::vector<std::vector<Entry>> per_flight(selected.size());
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, selected.size(), 16), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t si = r.begin(); si != r.end(); ++si) {
          const std::uint32_t fi = selected[si];
          const Flight& f = flights[fi];
          std::vector<Entry>& out = per_flight[si];
          double unwrap = 0;  // added to raw longitudes so that the trajectory is continuous
          for (std::uint32_t i = f.begin; i + 1 < f.end; ++i) {
            const double ta = p.t[i], tb = p.t[i + 1];
            const double lon_a = p.lon[i] + unwrap;
            const double dlon = lon_step(p.lon[i], p.lon[i + 1]);
            unwrap += (p.lon[i] + dlon) - p.lon[i + 1];
            if (!airborne(p, i) || tb <= t0 || ta >= t1 || !(tb > ta)) continue;
            const double lo = std::max(ta, t0), hi = std::min(tb, t1);
            std::size_t k = static_cast<std::size_t>(std::floor((lo - t0) / kBucketSeconds));
            if (k >= n_buckets) k = n_buckets - 1;
            while (k > 0 && bucket_lo(k) > lo) --k;
            for (; k < n_buckets && bucket_lo(k) < hi; ++k) {
              const double s = std::max(lo, bucket_lo(k)), e = std::min(hi, bucket_lo(k + 1));
              double lat[2], lon[2], alt[2];
              for (int j = 0; j < 2; ++j) {
                const double w = ((j == 0 ? s : e) - ta) / (tb - ta);
                lat[j] = p.lat[i] + (static_cast<double>(p.lat[i + 1]) - p.lat[i]) * w;
                lon[j] = lon_a + dlon * w;
                alt[j] = p.alt[i] + (static_cast<double>(p.alt[i + 1]) - p.alt[i]) * w;
              }
              Entry en{static_cast<std::uint32_t>(k),
                       fi,
                       static_cast<float>(std::min(lat[0], lat[1])),
                       static_cast<float>(std::max(lat[0], lat[1])),
                       static_cast<float>(std::min(alt[0], alt[1])),
                       static_cast<float>(std::max(alt[0], alt[1])),
                       std::min(lon[0], lon[1]),
                       std::max(lon[0], lon[1])};
              // Float rounding of the box: widen by one float ulp-ish step on both sides.
              en.lat_lo = std::nextafter(en.lat_lo, -kInf), en.lat_hi = std::nextafter(en.lat_hi, kInf);
              en.alt_lo = std::nextafter(en.alt_lo, -kInf), en.alt_hi = std::nextafter(en.alt_hi, kInf);
              if (!out.empty() && out.back().bucket == en.bucket) {
                Entry& b = out.back();
                b.lat_lo = std::min(b.lat_lo, en.lat_lo), b.lat_hi = std::max(b.lat_hi, en.lat_hi);
                b.alt_lo = std::min(b.alt_lo, en.alt_lo), b.alt_hi = std::max(b.alt_hi, en.alt_hi);
                b.lon_lo = std::min(b.lon_lo, en.lon_lo), b.lon_hi = std::max(b.lon_hi, en.lon_hi);
              } else {
                out.push_back(en);
              }
            }
          }
          // Grow each box (see the proof above) and bring lon_lo into [-180, 180).
          for (Entry& en : out) {
            const double big = std::max(std::fabs(en.lat_lo), std::fabs(en.lat_hi));
            const double cosb = std::cos(std::min(big, 90.0) * kDeg);
            const double h = cosb > 1e-9 ? kSafety * h_reach / (kA * cosb) / kDeg : 360.0;
            en.lat_lo = static_cast<float>(en.lat_lo - lat_grow),
            en.lat_hi = static_cast<float>(en.lat_hi + lat_grow);
            en.lat_lo = std::nextafter(en.lat_lo, -kInf), en.lat_hi = std::nextafter(en.lat_hi, kInf);
            en.lon_lo -= std::min(h, 360.0), en.lon_hi += std::min(h, 360.0);
            const double sh = wrap_lon(en.lon_lo) - en.lon_lo;
            en.lon_lo += sh, en.lon_hi += sh;
            en.alt_lo = static_cast<float>(en.alt_lo - 0.5 * c.v_max);
            en.alt_hi = static_cast<float>(en.alt_hi + 0.5 * c.v_max);
            en.alt_lo = std::nextafter(en.alt_lo, -kInf), en.alt_hi = std::nextafter(en.alt_hi, kInf);
          }
        }
      });

  // Entries grouped by bucket (a counting sort).
  std::vector<std::size_t> offset(n_buckets + 1, 0);
  for (const auto& v : per_flight)
    for (const Entry& en : v) ++offset[en.bucket + 1];
  for (std::size_t k = 0; k < n_buckets; ++k) offset[k + 1] += offset[k];
  std::vector<Entry> entries(offset.back());
  {
    std::vector<std::size_t> fill(offset.begin(), offset.end() - 1);
    for (auto& v : per_flight) {
      for (const Entry& en : v) entries[fill[en.bucket]++] = en;
      std::vector<Entry>().swap(v);
    }
  }

  // ---- 2. per bucket: candidate pairs from the hash, then the exact solve ------------------------------
  std::vector<std::vector<Part>> spans(n_buckets);
  std::vector<std::size_t> candidates(n_buckets, 0);
  std::vector<std::vector<std::uint64_t>> tested(n_buckets);
  const auto do_bucket = [&](std::size_t k) {
    const std::size_t b0 = offset[k], b1 = offset[k + 1];
    if (b1 - b0 < 2) return;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> cells;  // (cell key, entry index)
    for (std::size_t i = b0; i < b1; ++i) {
      const Entry& en = entries[i];
      const int la =
          std::clamp(static_cast<int>(std::floor((en.lat_lo + 90.0) / kCellDeg)), 0, kLatCells - 1);
      const int lb =
          std::clamp(static_cast<int>(std::floor((en.lat_hi + 90.0) / kCellDeg)), 0, kLatCells - 1);
      const long oa = static_cast<long>(std::floor((en.lon_lo + 180.0) / kCellDeg));
      long ob = static_cast<long>(std::floor((en.lon_hi + 180.0) / kCellDeg));
      if (ob - oa >= kLonCells) ob = oa + kLonCells - 1;
      for (int y = la; y <= lb; ++y)
        for (long x = oa; x <= ob; ++x) {
          const long xm = ((x % kLonCells) + kLonCells) % kLonCells;
          cells.emplace_back(static_cast<std::uint32_t>(y * kLonCells + xm), static_cast<std::uint32_t>(i));
        }
    }
    std::sort(cells.begin(), cells.end());
    std::vector<std::uint64_t> pairs;
    for (std::size_t i = 0; i < cells.size();) {
      std::size_t j = i;
      while (j < cells.size() && cells[j].first == cells[i].first) ++j;
      for (std::size_t u = i; u < j; ++u)
        for (std::size_t v = u + 1; v < j; ++v) {
          const Entry& x = entries[cells[u].second];
          const Entry& y = entries[cells[v].second];
          if (x.lat_hi < y.lat_lo || y.lat_hi < x.lat_lo || x.alt_hi < y.alt_lo || y.alt_hi < x.alt_lo)
            continue;
          bool lon = false;
          for (int w = -1; w <= 1 && !lon; ++w)
            lon = !(x.lon_hi < y.lon_lo + 360.0 * w || y.lon_hi + 360.0 * w < x.lon_lo);
          if (!lon) continue;
          const std::uint32_t a = std::min(x.flight, y.flight), b = std::max(x.flight, y.flight);
          pairs.push_back(static_cast<std::uint64_t>(a) << 32 | b);
        }
      i = j;
    }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    candidates[k] = pairs.size();
    const double lo = bucket_lo(k), hi = bucket_lo(k + 1);
    for (const std::uint64_t key : pairs)
      solve_pair(c, static_cast<std::uint32_t>(key >> 32), static_cast<std::uint32_t>(key), lo, hi, spans[k]);
    tested[k] = std::move(pairs);
  };
  for (std::size_t k0 = 0; k0 < n_buckets; k0 += kBucketsPerChunk) {
    if (cancel) cancel->throw_if_cancelled();
    const std::size_t k1 = std::min(n_buckets, k0 + kBucketsPerChunk);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(k0, k1, 1),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t k = r.begin(); k != r.end(); ++k) do_bucket(k);
                      });
    if (progress) progress(static_cast<double>(k1) / static_cast<double>(n_buckets), "separation");
  }
  if (cancel) cancel->throw_if_cancelled();

  // ---- 3. merge each pair's contiguous intervals across buckets into events ---------------------------
  std::vector<std::uint64_t> all_tested;
  std::vector<Part> all;
  for (std::size_t k = 0; k < n_buckets; ++k) {
    res.candidate_pairs += candidates[k];
    all_tested.insert(all_tested.end(), tested[k].begin(), tested[k].end());
    all.insert(all.end(), spans[k].begin(), spans[k].end());
    std::vector<Part>().swap(spans[k]);
  }
  std::sort(all_tested.begin(), all_tested.end());
  res.pairs_tested =
      static_cast<std::size_t>(std::unique(all_tested.begin(), all_tested.end()) - all_tested.begin());
  std::sort(all.begin(), all.end(), [](const Part& x, const Part& y) {
    if (x.a != y.a) return x.a < y.a;
    if (x.b != y.b) return x.b < y.b;
    return x.start < y.start;
  });
  // Chains of contiguous parts of one pair; each chain with a strict part is one event, from its first
  // strict start to its last strict end.
  std::vector<Part> merged;
  std::uint64_t last_pair = ~std::uint64_t{0};
  bool open = false;  // merged.back() is the event of the current chain
  for (std::size_t i = 0; i < all.size(); ++i) {
    const Part& part = all[i];
    const bool chained =
        i > 0 && all[i - 1].a == part.a && all[i - 1].b == part.b && all[i - 1].end == part.start;
    if (!chained) open = false;
    if (!part.strict) continue;
    if (open) {
      Part& ev = merged.back();
      ev.end = part.end;
      if (part.cpa_h < ev.cpa_h)
        ev.cpa_t = part.cpa_t, ev.cpa_h = part.cpa_h, ev.cpa_v = part.cpa_v, ev.cpa_seg_a = part.cpa_seg_a,
        ev.cpa_seg_b = part.cpa_seg_b;
      ev.min_v = std::min(ev.min_v, part.min_v);
    } else {
      merged.push_back(part);
      open = true;
      const std::uint64_t pair = static_cast<std::uint64_t>(part.a) << 32 | part.b;
      if (pair != last_pair) ++res.pairs_with_events, last_pair = pair;
    }
  }
  if (merged.size() > limits::kMaxSeparationEvents)
    throw Error(Error::Kind::payload_too_large, "max_events",
                std::to_string(merged.size()) + " losses of separation in the window, more than " +
                    std::to_string(limits::kMaxSeparationEvents) +
                    "; narrow it with t0/t1, bbox, alt_min/alt_max, callsign or icao24");

  res.events.reserve(merged.size());
  for (const Part& sp : merged) {
    const Flight& A = flights[sp.a];
    const Flight& B = flights[sp.b];
    SeparationEvent ev;
    ev.flight_a = sp.a, ev.flight_b = sp.b;
    ev.icao24_a = A.icao24, ev.callsign_a = A.callsign, ev.icao24_b = B.icao24, ev.callsign_b = B.callsign;
    ev.t_start = sp.start, ev.t_end = sp.end;
    ev.clipped_start = sp.start == t0 && A.t_min < t0 && B.t_min < t0;
    ev.clipped_end = sp.end == t1 && A.t_max > t1 && B.t_max > t1;
    ev.cpa_t = sp.cpa_t, ev.cpa_horizontal_m = sp.cpa_h, ev.cpa_vertical_m = sp.cpa_v;
    ev.min_vertical_m = sp.min_v;
    const Lin la = on_segment(p, sp.cpa_seg_a, sp.cpa_t), lb = on_segment(p, sp.cpa_seg_b, sp.cpa_t);
    ev.cpa_lat_a = la.lat, ev.cpa_lon_a = wrap_lon(la.lon), ev.cpa_alt_a_m = la.alt;
    ev.cpa_lat_b = lb.lat, ev.cpa_lon_b = wrap_lon(lb.lon), ev.cpa_alt_b_m = lb.alt;
    res.events.push_back(std::move(ev));
  }
  std::sort(res.events.begin(), res.events.end(), [](const SeparationEvent& x, const SeparationEvent& y) {
    if (x.t_start != y.t_start) return x.t_start < y.t_start;
    if (x.flight_a != y.flight_a) return x.flight_a < y.flight_a;
    return x.flight_b < y.flight_b;
  });
  return res;
}

nlohmann::json SeparationResult::to_json() const {
  nlohmann::json list = nlohmann::json::array();
  for (const SeparationEvent& e : events) {
    list.push_back({{"flight_a", e.flight_a},
                    {"icao24_a", e.icao24_a},
                    {"callsign_a", e.callsign_a},
                    {"flight_b", e.flight_b},
                    {"icao24_b", e.icao24_b},
                    {"callsign_b", e.callsign_b},
                    {"t_start", e.t_start},
                    {"t_end", e.t_end},
                    {"duration_s", e.t_end - e.t_start},
                    {"clipped_start", e.clipped_start},
                    {"clipped_end", e.clipped_end},
                    {"cpa",
                     {{"t", e.cpa_t},
                      {"horizontal_m", e.cpa_horizontal_m},
                      {"vertical_m", e.cpa_vertical_m},
                      {"a", {{"lat", e.cpa_lat_a}, {"lon", e.cpa_lon_a}, {"alt_m", e.cpa_alt_a_m}}},
                      {"b", {{"lat", e.cpa_lat_b}, {"lon", e.cpa_lon_b}, {"alt_m", e.cpa_alt_b_m}}}}},
                    {"min_vertical_m", e.min_vertical_m}});
  }
  return {{"t0", t0},
          {"t1", t1},
          {"minima",
           {{"horizontal_m", minima.horizontal_m},
            {"vertical_m", minima.vertical_m},
            {"vertical_high_m", minima.vertical_high_m},
            {"high_above_m", minima.high_above_m}}},
          {"flights", flights},
          {"candidate_pairs", candidate_pairs},
          {"pairs_tested", pairs_tested},
          {"pairs_with_events", pairs_with_events},
          {"count", events.size()},
          {"events", std::move(list)}};
}

namespace {
void csv_field(std::string& s, const std::string& v) {
  if (v.find_first_of(",\"\n\r") == std::string::npos) {
    s += v;
    return;
  }
  s += '"';
  for (const char ch : v) {
    if (ch == '"') s += '"';
    s += ch;
  }
  s += '"';
}
}  // namespace

std::string SeparationResult::to_csv() const {
  std::string s =
      "flight_a,icao24_a,callsign_a,flight_b,icao24_b,callsign_b,t_start,t_end,duration_s,clipped_start,"
      "clipped_end,cpa_t,cpa_horizontal_m,cpa_vertical_m,cpa_lat_a,cpa_lon_a,cpa_alt_a_m,cpa_lat_b,cpa_lon_b,"
      "cpa_alt_b_m,min_vertical_m\n";
  for (const SeparationEvent& e : events) {
    s += std::to_string(e.flight_a);
    s += ',';
    csv_field(s, e.icao24_a);
    s += ',';
    csv_field(s, e.callsign_a);
    s += ',';
    s += std::to_string(e.flight_b);
    s += ',';
    csv_field(s, e.icao24_b);
    s += ',';
    csv_field(s, e.callsign_b);
    for (const double v : {e.t_start, e.t_end, e.t_end - e.t_start}) {
      s += ',';
      append_shortest(s, v);
    }
    s += e.clipped_start ? ",true" : ",false";
    s += e.clipped_end ? ",true" : ",false";
    for (const double v : {e.cpa_t, e.cpa_horizontal_m, e.cpa_vertical_m, e.cpa_lat_a, e.cpa_lon_a,
                           e.cpa_alt_a_m, e.cpa_lat_b, e.cpa_lon_b, e.cpa_alt_b_m, e.min_vertical_m}) {
      s += ',';
      append_shortest(s, v);
    }
    s += '\n';
  }
  return s;
}

}  // namespace trailscope::congestion
