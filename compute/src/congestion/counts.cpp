#include "trailscope/congestion/counts.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <iterator>
#include <limits>
#include <numbers>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_sort.h>

#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/core/text.hpp"

namespace trailscope::congestion {

namespace {

constexpr std::uint64_t kNoKey = std::numeric_limits<std::uint64_t>::max();
constexpr double kDegToRad = std::numbers::pi / 180.0;

// Grid cell <-> key; keys sort as (row, col, layer). Packed into 33 bits (row < 540: 10 bits; col <
// 1080: 11 bits; layer + 2048: 12 bits, as a usable altitude, |alt| <= 1,000 km, is within 1,094 layers
// of 0), so that the radix sort below needs 3 passes of 11 bits.
constexpr int kLayerBits = 12, kColBits = 11;
constexpr int kLayerBias = 1 << (kLayerBits - 1);
std::uint64_t cell_key(const GridCell& c) {
  return (static_cast<std::uint64_t>(c.row) << (kColBits + kLayerBits)) |
         (static_cast<std::uint64_t>(c.col) << kLayerBits) | static_cast<std::uint64_t>(c.layer + kLayerBias);
}
GridCell key_cell(std::uint64_t k) {
  return {static_cast<int>(k >> (kColBits + kLayerBits)),
          static_cast<int>((k >> kLayerBits) & ((1 << kColBits) - 1)),
          static_cast<int>(k & ((1 << kLayerBits) - 1)) - kLayerBias};
}

// Stable LSD radix sort by `.key` of the concatenation of `parts` (per-thread buffers), into `out`;
// `tmp` is scratch. Only the bits in which the keys differ are sorted on, in passes of at most 11 bits
// (a 16 KiB histogram per pass): 3 passes for grid keys, 1 for sector indices. For the few hundred
// thousand records of a day on the grid this is several times faster than a comparison sort.
template <class T>
void radix_sort_by_key(const std::vector<std::vector<T>*>& parts, std::vector<T>& out, std::vector<T>& tmp) {
  std::size_t n = 0;
  std::uint64_t any = 0, all = ~std::uint64_t{0};
  for (const auto* p : parts) {
    n += p->size();
    for (const T& x : *p) any |= x.key, all &= x.key;
  }
  out.resize(n);
  const std::uint64_t varying = n ? any ^ all : 0;
  if (varying == 0) {  // one key (or none): the concatenation is sorted
    std::size_t at = 0;
    for (const auto* p : parts)
      at = static_cast<std::size_t>(std::copy(p->begin(), p->end(), out.begin() + at) - out.begin());
    return;
  }
  const int lo = std::countr_zero(varying), hi = 64 - std::countl_zero(varying);
  const int passes = (hi - lo + 10) / 11, bits = (hi - lo + passes - 1) / passes;
  const std::size_t buckets = std::size_t{1} << bits;
  const std::uint64_t mask = buckets - 1;
  std::vector<std::size_t> count(static_cast<std::size_t>(passes) * buckets, 0);
  for (const auto* p : parts)
    for (const T& x : *p)
      for (int d = 0; d < passes; ++d) ++count[d * buckets + ((x.key >> (lo + d * bits)) & mask)];
  for (int d = 0; d < passes; ++d) {
    std::size_t sum = 0;
    for (std::size_t b = 0; b < buckets; ++b) sum += std::exchange(count[d * buckets + b], sum);
  }
  tmp.resize(n);
  // The last pass must write `out`: start in `out` for an odd number of passes.
  std::vector<T>* dst = passes % 2 ? &out : &tmp;
  std::vector<T>* src = passes % 2 ? &tmp : &out;
  std::size_t* c0 = count.data();
  for (const auto* p : parts)
    for (const T& x : *p) (*dst)[c0[(x.key >> lo) & mask]++] = x;
  for (int d = 1; d < passes; ++d) {
    std::swap(src, dst);
    std::size_t* c = count.data() + d * buckets;
    const int shift = lo + d * bits;
    for (const T& x : *src) (*dst)[c[(x.key >> shift) & mask]++] = x;
  }
}

struct Pos {
  double lon = 0, lat = 0, alt = 0;
};

// A straight piece of trajectory: (lon, lat, alt) linear in time over [ta, tb], lon within [-180, 180].
struct Seg {
  double ta = 0, tb = 0;
  Pos p0, p1;
  double time(double u) const { return u <= 0 ? ta : u >= 1 ? tb : ta + (tb - ta) * u; }
  Pos at(double u) const {
    if (u <= 0) return p0;
    if (u >= 1) return p1;
    return {p0.lon + (p1.lon - p0.lon) * u, p0.lat + (p1.lat - p0.lat) * u, p0.alt + (p1.alt - p0.alt) * u};
  }
};

// Local flat distance in NM (1° of latitude = 60 NM; longitude scaled by the cosine of the mean
// latitude), the metric of the complexity attributes.
double flat_nm(const Pos& a, const Pos& b) {
  const double dlat = b.lat - a.lat;
  const double dlon = (b.lon - a.lon) * std::cos(0.5 * (a.lat + b.lat) * kDegToRad);
  return 60.0 * std::sqrt(dlat * dlat + dlon * dlon);
}

// A maximal interval of one flight's inside set in one volume.
struct Visit {
  std::uint64_t key = kNoKey;
  double a = 0, b = 0;
  bool ca = true, cb = true;
  Pos pa, pb;  // positions at a and b
  double path_nm = 0;
};

// What one flight contributes, collected per thread.
struct StepRange {
  std::uint64_t key;
  std::uint32_t flight, k0, k1;
};
struct EntryRange {
  std::uint64_t key;
  std::uint32_t j0, j1;
};
struct CVisit {  // a visit for the complexity score, clipped to [t0, t1)
  std::uint64_t key;
  std::uint32_t flight;
  double a, b;
  float heading, speed_kt;
  std::int8_t attitude;
};
struct Acc {
  std::vector<StepRange> ranges;
  std::vector<EntryRange> entries;
  std::vector<CVisit> cvisits;
  std::vector<std::uint64_t> present;  // volumes met in [t0, t1) that no period range names
  std::uint32_t flights = 0;
  // Per-flight scratch, reused.
  std::vector<StepRange> local;
  std::vector<std::uint64_t> prev, cur;
};

struct Timing {
  double t0, t1, step, dur, win, wstep;
  std::uint32_t K, J, H;
  // 1 / step and 1 / wstep: the first guesses below multiply instead of dividing (they run per sample);
  // the loops after each guess then find the exact index from s(k) and w(j), however the guess rounds.
  double inv_step = 0, inv_wstep = 0;
  double s(std::uint32_t k) const { return t0 + k * step; }
  double w(std::uint32_t j) const { return t0 + j * wstep; }
  // Periods meeting the set from a to b (ends closed as ca / cb; a == b a closed point); false if none.
  bool periods(double a, double b, bool cb, std::uint32_t& k0, std::uint32_t& k1) const {
    if (!(a < t1) || b < t0 || (b == t0 && !cb)) return false;
    // k1: largest k with s(k) < b (or <= b when b is in the set).
    // (Truncating a value >= 0 is flooring it.)
    long long hi = static_cast<long long>(std::min<double>((b - t0) * inv_step, K - 1.0));
    while (hi >= 0 && !(cb ? s(static_cast<std::uint32_t>(hi)) <= b : s(static_cast<std::uint32_t>(hi)) < b))
      --hi;
    while (hi + 1 < K &&
           (cb ? s(static_cast<std::uint32_t>(hi + 1)) <= b : s(static_cast<std::uint32_t>(hi + 1)) < b))
      ++hi;
    if (hi < 0) return false;
    // k0: smallest k with s(k) + dur > a.
    long long lo = static_cast<long long>(std::max(0.0, (a - dur - t0) * inv_step));
    while (lo > 0 && s(static_cast<std::uint32_t>(lo - 1)) + dur > a) --lo;
    while (lo <= hi && !(s(static_cast<std::uint32_t>(lo)) + dur > a)) ++lo;
    if (lo > hi) return false;
    k0 = static_cast<std::uint32_t>(lo), k1 = static_cast<std::uint32_t>(hi);
    return true;
  }
  // Entry windows holding the instant e (t0 <= e < t1).
  bool windows(double e, std::uint32_t& j0, std::uint32_t& j1) const {
    if (!(e >= t0 && e < t1)) return false;
    long long hi = static_cast<long long>(std::min<double>((e - t0) * inv_wstep, J - 1.0));
    while (hi >= 0 && w(static_cast<std::uint32_t>(hi)) > e) --hi;
    while (hi + 1 < J && w(static_cast<std::uint32_t>(hi + 1)) <= e) ++hi;
    if (hi < 0) return false;
    long long lo = static_cast<long long>(std::max(0.0, (e - win - t0) * inv_wstep));
    while (lo > 0 && w(static_cast<std::uint32_t>(lo - 1)) + win > e) --lo;
    while (lo <= hi && !(w(static_cast<std::uint32_t>(lo)) + win > e)) ++lo;
    if (lo > hi) return false;
    j0 = static_cast<std::uint32_t>(lo), j1 = static_cast<std::uint32_t>(hi);
    return true;
  }
};

double orient2(double ax, double ay, double bx, double by, double cx, double cy) {
  return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
}

struct SectorBox {
  double west, east, south, north, lower, upper;
};

// ---------------------------------------------------------------------------------------------------
// One flight: its inside sets as visits, in time order per volume.
class FlightScan {
 public:
  FlightScan(const CountsRequest& r, const GridExtent* extent, const std::vector<SectorBox>& boxes,
             const std::vector<std::array<int, 4>>* columns)
      : r_(r), extent_(extent), boxes_(boxes), columns_(columns) {}

  std::vector<Visit> visits;  // closed visits, in the order they end

  void reset() {
    visits.clear();
    open_.clear();
  }
  void finish() {
    for (auto& v : open_) visits.push_back(v);
    open_.clear();
  }

  // The key of a position (grid), kNoKey when outside the extent or the altitude is unknown.
  // An altitude the grid can place: known and within ±1,000 km (grid_cell_at refuses beyond ±10,000 km;
  // anything past the first is a damaged sample, not an aircraft).
  static bool usable(double alt) { return std::fabs(alt) <= 1e6; }
  std::uint64_t cell_of(const Pos& p) const {
    if (!usable(p.alt)) return kNoKey;
    const GridCell c = locate(p);
    return in_extent(c) ? cell_key(c) : kNoKey;
  }
  // The same without the extent: the cell holding p, kNoKey only for an unknown altitude.
  std::uint64_t raw_cell_of(const Pos& p) const {
    if (!usable(p.alt)) return kNoKey;
    return cell_key(locate(p));
  }
  bool sector_holds(std::size_t s, const Pos& p) const {
    const Sector& sec = r_.sectors[s];
    return p.alt >= sec.lower_m && p.alt <= sec.upper_m && polygon_contains(sec, p.lon, p.lat);
  }

  // A segment (already split at 180°); `first` emits the point at its start too.
  void segment(const Seg& s, bool first) {
    if (extent_)
      grid_segment(s, first);
    else
      for (std::size_t i = 0; i < boxes_.size(); ++i) sector_segment(s, i, first);
  }
  // A lone sample (a flight of one sample, or one bordered by unusable segments).
  void point(double t, const Pos& p) {
    if (extent_) {
      add(cell_of(p), t, t, true, true, p, p);
    } else {
      for (std::size_t i = 0; i < boxes_.size(); ++i)
        if (sector_holds(i, p)) add(i, t, t, true, true, p, p);
    }
  }

 private:
  const CountsRequest& r_;
  const GridExtent* extent_;
  // Per row of the grid, the extent's column ranges [a, b] and [c, d] (GridExtent::contains, cached).
  const std::vector<std::array<int, 4>>* columns_;
  const GridRowTable& rows_ = GridRowTable::get();
  // The cell of p, a usable altitude: grid_cell_at's cell without its checks (the TrailSet's
  // positions are finite, and interpolating between them keeps them so; the clamps keep them in range).
  GridCell locate(const Pos& p) const {
    return grid_cell_at_unchecked(rows_, std::clamp(p.lat, -90.0, 90.0), std::clamp(p.lon, -180.0, 180.0),
                                  p.alt);
  }
  bool in_extent(const GridCell& c) const {
    if (c.row < extent_->row_min || c.row > extent_->row_max || c.layer < extent_->layer_min ||
        c.layer > extent_->layer_max)
      return false;
    const auto& r = (*columns_)[static_cast<std::size_t>(c.row)];
    return (c.col >= r[0] && c.col <= r[1]) || (c.col >= r[2] && c.col <= r[3]);
  }
  const std::vector<SectorBox>& boxes_;
  std::vector<Visit> open_;
  std::vector<double> us_;
  std::vector<std::pair<double, int>> ubs_;

  void add(std::uint64_t key, double a, double b, bool ca, bool cb, const Pos& pa, const Pos& pb) {
    if (extent_) {
      // The grid partitions space: a flight is in one cell at a time, so another cell closes the visit.
      if (!open_.empty() && open_.back().key != key) {
        visits.push_back(open_.back());
        open_.clear();
      }
    }
    if (key == kNoKey) return;
    Visit* v = nullptr;
    for (auto it = open_.rbegin(); it != open_.rend(); ++it)
      if (it->key == key) {
        v = &*it;
        break;
      }
    if (v && v->b == a && (v->cb || ca)) {
      if (b > v->b || (b == v->b && cb)) {
        v->path_nm += flat_nm(v->pb, pb);
        v->b = b, v->cb = b == a ? (v->cb || cb) : cb, v->pb = pb;
      }
      return;
    }
    if (v) {
      visits.push_back(*v);
      *v = Visit{key, a, b, ca, cb, pa, pb, flat_nm(pa, pb)};
    } else {
      open_.push_back(Visit{key, a, b, ca, cb, pa, pb, flat_nm(pa, pb)});
    }
  }

  // Emits the pieces between sorted breakpoints us_ (first 0, last 1): points at breakpoints and open
  // pieces between, each classified by `key_at`.
  template <class KeyAt>
  void emit(const Seg& s, bool first, KeyAt key_at) {
    for (std::size_t i = 0; i < us_.size(); ++i) {
      const double u = us_[i];
      if (i > 0 || first) {
        const Pos p = s.at(u);
        add(key_at(p, static_cast<int>(i)), s.time(u), s.time(u), true, true, p, p);
      }
      if (i + 1 < us_.size()) {
        const double u2 = us_[i + 1];
        const Pos m = s.at(0.5 * (u + u2));
        add(key_at(m, -1), s.time(u), s.time(u2), false, false, s.at(u), s.at(u2));
      }
    }
  }

  void grid_segment(const Seg& s, bool first) {
    if (!usable(s.p0.alt) || !usable(s.p1.alt)) return;
    if (raw_cell_of(s.p0) == raw_cell_of(s.p1)) {
      // A half-open box is convex: both ends in one cell means the whole segment is.
      add(cell_of(s.p0), s.ta, s.tb, true, true, s.p0, s.p1);
      return;
    }
    const std::uint64_t k0 = cell_of(s.p0), k1 = cell_of(s.p1);
    us_.clear();
    us_.push_back(0);
    us_.push_back(1);
    const double lat0 = std::clamp(s.p0.lat, -90.0, 90.0), lat1 = std::clamp(s.p1.lat, -90.0, 90.0);
    const GridCell c0 = locate(s.p0);
    const GridCell c1 = locate(s.p1);
    const auto cross = [&](double v0, double v1, double x) {
      if (v1 == v0) return;
      const double u = (x - v0) / (v1 - v0);
      if (u > 0 && u < 1) us_.push_back(u);
    };
    // Row boundaries, and the column boundaries inside each row's part of the segment.
    const int rlo = std::min(c0.row, c1.row), rhi = std::max(c0.row, c1.row);
    for (int row = rlo; row <= rhi; ++row) {
      double ua = 0, ub = 1;
      if (lat1 != lat0) {
        const double south = -90.0 + row / 3.0, north = -90.0 + (row + 1) / 3.0;
        double u_s = (south - lat0) / (lat1 - lat0), u_n = (north - lat0) / (lat1 - lat0);
        ua = std::max(0.0, std::min(u_s, u_n));
        ub = std::min(1.0, std::max(u_s, u_n));
        if (row > rlo) cross(lat0, lat1, south);
      }
      const double lon_a = s.p0.lon + (s.p1.lon - s.p0.lon) * ua;
      const double lon_b = s.p0.lon + (s.p1.lon - s.p0.lon) * ub;
      const double lo = std::min(lon_a, lon_b), hi = std::max(lon_a, lon_b);
      const double w = grid_column_width(row);
      const int n = grid_columns(row);
      const int clo = std::clamp(static_cast<int>(std::floor((lo + 180.0) / w)) - 1, 0, n - 1);
      const int chi = std::clamp(static_cast<int>(std::floor((hi + 180.0) / w)) + 1, 0, n - 1);
      for (int c = clo + 1; c <= chi; ++c) {
        const double x = -180.0 + c * w;
        if (x < lo || x > hi) continue;
        const double u = (x - s.p0.lon) / (s.p1.lon - s.p0.lon);
        if (u > 0 && u < 1 && u >= ua - 1e-12 && u <= ub + 1e-12) us_.push_back(u);
      }
    }
    for (int l = std::min(c0.layer, c1.layer) + 1; l <= std::max(c0.layer, c1.layer); ++l)
      cross(s.p0.alt, s.p1.alt, l * kGridLayerMetres);
    std::sort(us_.begin(), us_.end());
    us_.erase(std::unique(us_.begin(), us_.end()), us_.end());
    emit(s, first, [&](const Pos& p, int i) {
      if (i == 0) return k0;
      if (i + 1 == static_cast<int>(us_.size())) return k1;
      return cell_of(p);
    });
  }

  void sector_segment(const Seg& s, std::size_t si, bool first) {
    const SectorBox& box = boxes_[si];
    if (!(s.p0.alt == s.p0.alt && s.p1.alt == s.p1.alt)) return;
    if (std::max(s.p0.lon, s.p1.lon) < box.west || std::min(s.p0.lon, s.p1.lon) > box.east ||
        std::max(s.p0.lat, s.p1.lat) < box.south || std::min(s.p0.lat, s.p1.lat) > box.north ||
        std::max(s.p0.alt, s.p1.alt) < box.lower || std::min(s.p0.alt, s.p1.alt) > box.upper)
      return;
    const Sector& sec = r_.sectors[si];
    // Breakpoints with what they are known to lie on: 1 a polygon edge, 2 an altitude bound.
    ubs_.clear();
    ubs_.push_back({0.0, 0});
    ubs_.push_back({1.0, 0});
    const double px = s.p0.lon, py = s.p0.lat, dx = s.p1.lon - s.p0.lon, dy = s.p1.lat - s.p0.lat;
    const double dd = dx * dx + dy * dy;
    const std::size_t n = sec.ring.size();
    if (dd > 0) {
      for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
        const double qx = sec.ring[j][0], qy = sec.ring[j][1], rx = sec.ring[i][0], ry = sec.ring[i][1];
        const double o1 = orient2(px, py, s.p1.lon, s.p1.lat, qx, qy);
        const double o2 = orient2(px, py, s.p1.lon, s.p1.lat, rx, ry);
        if ((o1 > 0 && o2 > 0) || (o1 < 0 && o2 < 0)) continue;
        const double o3 = orient2(qx, qy, rx, ry, px, py);
        const double o4 = orient2(qx, qy, rx, ry, s.p1.lon, s.p1.lat);
        if ((o3 > 0 && o4 > 0) || (o3 < 0 && o4 < 0)) continue;
        const auto proj = [&](double x, double y) { return ((x - px) * dx + (y - py) * dy) / dd; };
        if (o1 == 0 && o2 == 0) {
          // Collinear: the edge's ends that lie on the segment are breakpoints; between them the
          // segment runs along the boundary (inside, a closed set).
          for (double u : {proj(qx, qy), proj(rx, ry)})
            if (u > 0 && u < 1) ubs_.push_back({u, 1});
          continue;
        }
        double u;
        if (o1 == 0)
          u = proj(qx, qy);
        else if (o2 == 0)
          u = proj(rx, ry);
        else {
          const double ex = rx - qx, ey = ry - qy;
          u = ((qx - px) * ey - (qy - py) * ex) / (dx * ey - dy * ex);
        }
        u = std::clamp(u, 0.0, 1.0);
        ubs_.push_back({u, 1});
      }
    }
    const double a0 = s.p0.alt, a1 = s.p1.alt;
    if (a1 != a0)
      for (double z : {sec.lower_m, sec.upper_m}) {
        const double u = (z - a0) / (a1 - a0);
        if (u > 0 && u < 1) ubs_.push_back({u, 2});
      }
    std::sort(ubs_.begin(), ubs_.end());
    us_.clear();
    std::vector<int>& flags = flags_;
    flags.clear();
    for (const auto& [u, f] : ubs_) {
      if (!us_.empty() && us_.back() == u) {
        flags.back() |= f;
        continue;
      }
      us_.push_back(u);
      flags.push_back(f);
    }
    const std::uint64_t key = si;
    emit(s, first, [&](const Pos& p, int i) -> std::uint64_t {
      const int f = i >= 0 ? flags[static_cast<std::size_t>(i)] : 0;
      const bool horiz = (f & 1) || polygon_contains(sec, p.lon, p.lat);
      const bool vert = (f & 2) || (p.alt >= sec.lower_m && p.alt <= sec.upper_m);
      return horiz && vert ? key : kNoKey;
    });
  }
  std::vector<int> flags_;
};

// Splits a sample-to-sample segment at 180° (the short way round, as positions.hpp decides it) and feeds
// the parts to the scan.
void feed_segment(FlightScan& scan, double ta, double tb, const Pos& a, const Pos& b, bool first) {
  if (std::fabs(static_cast<float>(b.lon) - static_cast<float>(a.lon)) > 180.0f) {
    const double d = b.lon - a.lon;
    const double b_unwrapped = b.lon + (d > 0 ? -360.0 : 360.0);
    const double edge = d > 0 ? -180.0 : 180.0;  // where the first part leaves
    const double u = (edge - a.lon) / (b_unwrapped - a.lon);
    const double tc = ta + (tb - ta) * u;
    const Pos mid{edge, a.lat + (b.lat - a.lat) * u, a.alt + (b.alt - a.alt) * u};
    const Pos mid2{-edge, mid.lat, mid.alt};
    scan.segment(Seg{ta, tc, a, mid}, first);
    scan.segment(Seg{tc, tb, mid2, b}, false);
    return;
  }
  scan.segment(Seg{ta, tb, a, b}, first);
}

std::int8_t attitude(double vrate_fpm, double threshold) {
  return vrate_fpm > threshold ? 1 : vrate_fpm < -threshold ? -1 : 0;
}

void merge_ranges(std::vector<StepRange>& rs, std::size_t from, std::vector<StepRange>& out) {
  std::sort(
      rs.begin() + static_cast<std::ptrdiff_t>(from), rs.end(),
      [](const StepRange& x, const StepRange& y) { return x.key != y.key ? x.key < y.key : x.k0 < y.k0; });
  for (std::size_t i = from; i < rs.size(); ++i) {
    if (!out.empty() && out.back().key == rs[i].key && out.back().flight == rs[i].flight &&
        rs[i].k0 <= out.back().k1 + 1) {
      out.back().k1 = std::max(out.back().k1, rs[i].k1);
      continue;
    }
    out.push_back(rs[i]);
  }
}

double need_number(const std::map<std::string, std::string>& p, const char* key, double fallback) {
  const auto it = p.find(key);
  if (it == p.end()) return fallback;
  const std::string& s = it->second;
  double v = 0;
  std::size_t used = 0;
  try {
    v = std::stod(s, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (s.empty() || used != s.size() || !std::isfinite(v))
    throw invalid_argument(key, std::string(key) + ": '" + s + "' is not a number");
  return v;
}

}  // namespace

const char* to_string(Method m) noexcept {
  return m == Method::samples ? "samples" : "interpolated";
}

Method parse_method(const std::string& text) {
  if (text == "interpolated") return Method::interpolated;
  if (text == "samples") return Method::samples;
  throw invalid_argument("method", "method must be 'interpolated' or 'samples', got '" + text + "'");
}

const char* to_string(HotspotKind k) noexcept {
  return k == HotspotKind::sustained ? "sustained" : "peak";
}

void validate(const CountsRequest& r) {
  const Query& q = r.query;
  if (!q.t0) throw invalid_argument("t0", "t0 is required: congestion counts need a time window [t0, t1)");
  if (!q.t1) throw invalid_argument("t1", "t1 is required: congestion counts need a time window [t0, t1)");
  if (!std::isfinite(*q.t0)) throw invalid_argument("t0", "t0 must be a finite time");
  if (!std::isfinite(*q.t1)) throw invalid_argument("t1", "t1 must be a finite time");
  if (*q.t1 <= *q.t0) throw invalid_argument("t1", "t1 must be later than t0 (the window is [t0, t1))");
  if (*q.t1 - *q.t0 > limits::kMaxCongestionSpanSeconds)
    throw invalid_argument("t1", "t1 - t0 exceeds the longest congestion window of " +
                                     format_double(limits::kMaxCongestionSpanSeconds / 86400.0) + " days");
  if (q.on_ground)
    throw invalid_argument("on_ground",
                           "on_ground does not apply to congestion counts (trajectories are airborne)");
  const auto range = [](double v, double lo, double hi, const char* param, const char* what) {
    if (!(std::isfinite(v) && v >= lo && v <= hi))
      throw invalid_argument(param, std::string(param) + " must lie in [" + format_double(lo) + ", " +
                                        format_double(hi) + "] " + what + ", got " + format_double(v));
  };
  range(r.step_s, 1, 3600, "step", "seconds");
  range(r.duration_s, 60, 3600, "duration", "seconds");
  range(r.entry_window_s, 60, 86400, "entry_window", "seconds");
  range(r.entry_step_s, 60, 86400, "entry_step", "seconds");
  for (const auto& [thr, name] : {std::pair{r.peak, "peak"}, std::pair{r.sustained, "sustained"}})
    if (thr && !(std::isfinite(*thr) && *thr >= 0))
      throw invalid_argument(
          name, std::string(name) + " must be a number of flights >= 0, got " + format_double(*thr));
  if (r.sustained_steps < 1 || r.sustained_steps > 10000)
    throw invalid_argument("sustained_steps", "sustained_steps must lie in [1, 10000]");
  const auto& c = r.complexity_params;
  if (!(c.heading_deg > 0 && c.heading_deg < 180))
    throw invalid_argument("heading_deg", "heading_deg must lie in (0, 180) degrees");
  if (!(c.speed_kt > 0 && std::isfinite(c.speed_kt)))
    throw invalid_argument("speed_kt", "speed_kt must be a positive speed in knots");
  if (!(c.vrate_fpm > 0 && std::isfinite(c.vrate_fpm)))
    throw invalid_argument("vrate_fpm", "vrate_fpm must be a positive vertical rate in ft/min");
  const double span = *q.t1 - *q.t0;
  if (std::ceil(span / r.step_s) > static_cast<double>(limits::kMaxCongestionSteps))
    throw Error(Error::Kind::payload_too_large, "step",
                "the window holds " + format_double(std::ceil(span / r.step_s)) +
                    " counting periods, more than the limit of " +
                    std::to_string(limits::kMaxCongestionSteps) + "; use a longer step or a shorter window");
  if (std::ceil(span / r.entry_step_s) > static_cast<double>(limits::kMaxCongestionSteps))
    throw Error(Error::Kind::payload_too_large, "entry_step",
                "the window holds more entry windows than the limit of " +
                    std::to_string(limits::kMaxCongestionSteps));
  if (!r.sectors.empty()) {
    if (q.bbox)
      throw invalid_argument("bbox", "bbox selects the grid's extent; it does not apply to sectors");
    if (q.alt_min)
      throw invalid_argument("alt_min",
                             "alt_min selects the grid's layers; sectors have their own flight levels");
    if (q.alt_max)
      throw invalid_argument("alt_max",
                             "alt_max selects the grid's layers; sectors have their own flight levels");
    if (r.sectors.size() > limits::kMaxSectors)
      throw Error(Error::Kind::payload_too_large, "sectors",
                  std::to_string(r.sectors.size()) + " sectors, more than the limit of " +
                      std::to_string(limits::kMaxSectors));
  } else {
    make_grid_extent(q.bbox.value_or(BBox{}), q.alt_min.value_or(0.0),
                     q.alt_max.value_or(60000.0 * kMetresPerFoot));
  }
}

CountsRequest parse_counts_request(const std::map<std::string, std::string>& params) {
  CountsRequest r;
  r.query = parse_query(params);
  r.step_s = need_number(params, "step", r.step_s);
  r.duration_s = need_number(params, "duration", r.duration_s);
  r.entry_window_s = need_number(params, "entry_window", r.entry_window_s);
  r.entry_step_s = need_number(params, "entry_step", r.entry_step_s);
  if (auto it = params.find("method"); it != params.end()) r.method = parse_method(it->second);
  if (params.count("peak")) r.peak = need_number(params, "peak", 0);
  if (params.count("sustained")) r.sustained = need_number(params, "sustained", 0);
  if (params.count("sustained_steps")) {
    const double n = need_number(params, "sustained_steps", 0);
    if (n != std::floor(n) || n < 1 || n > 10000)
      throw invalid_argument("sustained_steps", "sustained_steps must be a whole number in [1, 10000]");
    r.sustained_steps = static_cast<int>(n);
  }
  if (auto it = params.find("complexity"); it != params.end()) {
    if (it->second != "true" && it->second != "false")
      throw invalid_argument("complexity", "complexity must be true or false, got '" + it->second + "'");
    r.complexity = it->second == "true";
  }
  r.complexity_params.heading_deg = need_number(params, "heading_deg", r.complexity_params.heading_deg);
  r.complexity_params.speed_kt = need_number(params, "speed_kt", r.complexity_params.speed_kt);
  r.complexity_params.vrate_fpm = need_number(params, "vrate_fpm", r.complexity_params.vrate_fpm);
  validate(r);
  return r;
}

// --- results helpers -------------------------------------------------------------------------------

std::vector<std::uint32_t> Series::dense(std::size_t n) const {
  std::vector<std::uint32_t> d(n, 0);
  for (std::size_t i = 0; i < index.size(); ++i)
    if (index[i] < n) d[index[i]] = value[i];
  return d;
}
std::uint32_t Series::max() const {
  return value.empty() ? 0 : *std::max_element(value.begin(), value.end());
}
std::uint64_t Series::sum() const {
  std::uint64_t s = 0;
  for (auto v : value) s += v;
  return s;
}

double ComplexityCell::adjusted_density() const {
  return flight_hours > 0 ? 60.0 * interaction_hours / flight_hours : 0.0;
}
double ComplexityCell::structural_index() const {
  return interaction_hours > 0 ? (horizontal_hours + vertical_hours + speed_hours) / interaction_hours : 0.0;
}
double ComplexityCell::score() const {
  return adjusted_density() * structural_index();
}

// --- count -----------------------------------------------------------------------------------------

CountsResult count(const TrailSet& set, const CountsRequest& r, const ProgressFn& progress,
                   const CancelToken* cancel) {
  validate(r);
  const Query& q = r.query;
  const double t0 = *q.t0, t1 = *q.t1;
  Timing tm{t0, t1, r.step_s, r.duration_s, r.entry_window_s, r.entry_step_s, 0, 0, 0};
  tm.K = static_cast<std::uint32_t>(std::ceil((t1 - t0) / r.step_s));
  tm.J = static_cast<std::uint32_t>(std::ceil((t1 - t0) / r.entry_step_s));
  tm.H = static_cast<std::uint32_t>(std::ceil((t1 - t0) / 3600.0));
  tm.inv_step = 1.0 / r.step_s, tm.inv_wstep = 1.0 / r.entry_step_s;

  const bool grid = r.sectors.empty();
  std::optional<GridExtent> extent;
  if (grid)
    extent = make_grid_extent(q.bbox.value_or(BBox{}), q.alt_min.value_or(0.0),
                              q.alt_max.value_or(60000.0 * kMetresPerFoot));
  std::vector<SectorBox> boxes;
  for (const auto& s : r.sectors) {
    SectorBox b{180, -180, 90, -90, s.lower_m, s.upper_m};
    for (const auto& p : s.ring) {
      b.west = std::min(b.west, p[0]), b.east = std::max(b.east, p[0]);
      b.south = std::min(b.south, p[1]), b.north = std::max(b.north, p[1]);
    }
    boxes.push_back(b);
  }
  const GridExtent* ext = extent ? &*extent : nullptr;
  const std::string too_big_param = grid ? "bbox" : "sectors";

  const auto& pts = set.points();
  const auto& flights = set.flights();
  const bool interpolated = r.method == Method::interpolated;
  const bool need_visits = interpolated || r.complexity;
  const double vrate_thr = r.complexity_params.vrate_fpm;

  tbb::enumerable_thread_specific<Acc> accs;
  // The extent's columns per row (GridExtent::contains's rule: the columns meeting the bbox's
  // longitudes, two runs when it crosses 180°), cached for the inner loop.
  std::vector<std::array<int, 4>> columns(kGridRows, std::array<int, 4>{1, 0, 1, 0});
  if (ext)
    for (int row = ext->row_min; row <= ext->row_max; ++row) {
      const double lat = -90.0 + (row + 0.5) / 3.0;
      const int n = grid_columns(row);
      const auto col = [&](double lon) { return grid_cell_at(lat, lon, 0).col; };
      auto& c = columns[static_cast<std::size_t>(row)];
      if (ext->bbox.west <= ext->bbox.east)
        c = {col(ext->bbox.west), ext->bbox.east >= 180 ? n - 1 : col(ext->bbox.east), 1, 0};
      else
        c = {col(ext->bbox.west), n - 1, 0, col(ext->bbox.east)};
    }
  tbb::enumerable_thread_specific<FlightScan> scans([&] { return FlightScan(r, ext, boxes, &columns); });
  std::atomic<std::size_t> total_visits{0};

  const auto pos_of = [&](std::size_t i) { return Pos{pts.lon[i], pts.lat[i], pts.alt[i]}; };

  const auto do_flight = [&](std::uint32_t fi, Acc& acc, FlightScan& scan) {
    const Flight& f = flights[fi];
    if (f.begin == f.end || f.t_max < t0 || f.t_min >= t1 || !q.matches_flight_ids(f)) return;
    ++acc.flights;
    const double* const tb = pts.t.data() + f.begin;
    const double* const te = pts.t.data() + f.end;
    // i0: the last sample before t0 (or the first sample); i1: one past the last sample before t1,
    // plus the one after it (the segment that crosses t1).
    std::size_t i0 = f.begin + static_cast<std::size_t>(std::lower_bound(tb, te, t0) - tb);
    if (i0 > f.begin) --i0;
    std::size_t i1 = f.begin + static_cast<std::size_t>(std::lower_bound(tb, te, t1) - tb);
    if (i1 < f.end) ++i1;  // [i0, i1)
    std::vector<StepRange>& local = acc.local;
    local.clear();

    if (need_visits) {
      scan.reset();
      bool first = true;
      for (std::size_t i = i0; i + 1 < i1; ++i) {
        const Pos a = pos_of(i), b = pos_of(i + 1);
        if (!(pts.t[i + 1] > pts.t[i]) || !(a.alt == a.alt) || !(b.alt == b.alt)) {
          if (first) scan.point(pts.t[i], a);
          first = true;
          continue;
        }
        feed_segment(scan, pts.t[i], pts.t[i + 1], a, b, first);
        first = false;
      }
      if (first && i1 > i0) scan.point(pts.t[i1 - 1], pos_of(i1 - 1));
      scan.finish();
      total_visits.fetch_add(scan.visits.size(), std::memory_order_relaxed);
      for (const Visit& v : scan.visits) {
        std::uint32_t k0 = 0, k1 = 0;
        const bool meets = tm.periods(v.a, v.b, v.cb, k0, k1);
        if (!(v.a < t1) || v.b < t0 || (v.b == t0 && !v.cb)) continue;  // not in [t0, t1)
        if (interpolated) {
          if (meets)
            local.push_back({v.key, fi, k0, k1});
          else
            acc.present.push_back(v.key);
          std::uint32_t j0 = 0, j1 = 0;
          if (tm.windows(v.a, j0, j1)) acc.entries.push_back({v.key, j0, j1});
        }
        if (r.complexity) {
          const double a = std::max(v.a, t0), b = std::min(v.b, t1);
          if (b > a) {
            const double dt = v.b - v.a;
            const double dlat = v.pb.lat - v.pa.lat;
            double dlon = v.pb.lon - v.pa.lon;
            if (dlon > 180) dlon -= 360;
            if (dlon < -180) dlon += 360;
            dlon *= std::cos(0.5 * (v.pa.lat + v.pb.lat) * kDegToRad);
            const float heading =
                (dlat == 0 && dlon == 0)
                    ? std::numeric_limits<float>::quiet_NaN()
                    : static_cast<float>(std::fmod(std::atan2(dlon, dlat) / kDegToRad + 360.0, 360.0));
            const double speed = v.path_nm / (dt / 3600.0);
            const double vrate = (v.pb.alt - v.pa.alt) / kMetresPerFoot / (dt / 60.0);
            acc.cvisits.push_back(
                {v.key, fi, a, b, heading, static_cast<float>(speed), attitude(vrate, vrate_thr)});
          }
        }
      }
    }
    if (interpolated) {
      merge_ranges(local, 0, acc.ranges);
      return;
    }
    // method = samples: the volumes holding each sample; a sample in a volume that the flight's
    // previous sample is not in enters it. Samples come in time order, so a volume's period ranges
    // come with non-decreasing ends: joining each to the flight's last range in that volume when they
    // overlap or touch gives merge_ranges' disjoint ranges without its sort. That last range is looked
    // for among the flight's last 64 ranges only (a bound on the work per sample); when it may lie
    // further back, merge_ranges does the flight's ranges afterwards.
    std::vector<StepRange>& out = acc.ranges;
    const std::size_t flight_start = out.size();
    bool unmerged = false;
    const auto add_range = [&](std::uint64_t k, std::uint32_t k0, std::uint32_t k1) {
      constexpr std::size_t kLookBack = 64;
      const std::size_t stop = std::max(flight_start, out.size() > kLookBack ? out.size() - kLookBack : 0);
      for (std::size_t x = out.size(); x-- > stop;)
        if (out[x].key == k) {
          if (k0 <= out[x].k1 + 1) {
            out[x].k1 = std::max(out[x].k1, k1);
            return;
          }
          out.push_back({k, fi, k0, k1});
          return;
        }
      if (stop > flight_start) unmerged = true;
      out.push_back({k, fi, k0, k1});
    };
    const auto count_sample = [&](std::uint64_t k, double t, bool entered) {
      std::uint32_t k0 = 0, k1 = 0;
      if (tm.periods(t, t, true, k0, k1))
        add_range(k, k0, k1);
      else
        acc.present.push_back(k);
      std::uint32_t j0 = 0, j1 = 0;
      if (entered && tm.windows(t, j0, j1)) acc.entries.push_back({k, j0, j1});
    };
    if (ext) {
      // The grid partitions space: a sample is in at most one cell (kNoKey: none, or no altitude).
      std::uint64_t prev = kNoKey;
      for (std::size_t i = i0; i < i1; ++i) {
        const double t = pts.t[i];
        if (t >= t1) break;
        const std::uint64_t k = scan.cell_of(pos_of(i));
        if (t >= t0 && k != kNoKey) count_sample(k, t, i == i0 || k != prev);
        prev = k;
      }
    } else {
      std::vector<std::uint64_t>& prev = acc.prev;
      std::vector<std::uint64_t>& cur = acc.cur;
      prev.clear();
      for (std::size_t i = i0; i < i1; ++i) {
        const double t = pts.t[i];
        if (t >= t1) break;
        const Pos p = pos_of(i);
        cur.clear();
        if (p.alt == p.alt)
          for (std::size_t s = 0; s < boxes.size(); ++s)
            if (scan.sector_holds(s, p)) cur.push_back(s);
        if (t >= t0)
          for (std::uint64_t k : cur)
            count_sample(k, t, i == i0 || std::find(prev.begin(), prev.end(), k) == prev.end());
        std::swap(prev, cur);
      }
    }
    if (unmerged) {
      local.assign(out.begin() + static_cast<std::ptrdiff_t>(flight_start), out.end());
      out.resize(flight_start);
      merge_ranges(local, 0, out);
    }
  };

  // Flights in blocks, so that progress and cancellation are reported from this thread.
  const std::uint32_t nf = static_cast<std::uint32_t>(flights.size());
  const std::uint32_t block = std::max<std::uint32_t>(256, nf / 50 + 1);
  for (std::uint32_t start = 0; start < nf; start += block) {
    if (cancel) cancel->throw_if_cancelled();
    const std::uint32_t stop = std::min(nf, start + block);
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(start, stop, 64), [&](const auto& br) {
      Acc& acc = accs.local();
      FlightScan& scan = scans.local();
      for (std::uint32_t fi = br.begin(); fi != br.end(); ++fi) do_flight(fi, acc, scan);
    });
    if (total_visits.load() > limits::kMaxCongestionPieces)
      throw Error(Error::Kind::payload_too_large, too_big_param,
                  "more than " + std::to_string(limits::kMaxCongestionPieces) +
                      " volume visits; narrow the window, the flights or the volumes");
    if (progress) progress(static_cast<double>(stop) / std::max<std::uint32_t>(nf, 1), "inside");
  }
  if (cancel) cancel->throw_if_cancelled();

  // Gather. Ranges and entries by volume only (a stable radix sort, straight from the per-thread
  // buffers): a volume's series and its hotspots' flight lists do not depend on the order inside.
  std::vector<StepRange> ranges, ranges_tmp;
  std::vector<EntryRange> entries, entries_tmp;
  std::vector<CVisit> cvisits;
  std::vector<std::uint64_t> present;
  CountsResult res;
  {
    std::vector<std::vector<StepRange>*> range_parts;
    std::vector<std::vector<EntryRange>*> entry_parts;
    std::size_t nc = 0, np = 0;
    for (auto& a : accs) {
      range_parts.push_back(&a.ranges), entry_parts.push_back(&a.entries);
      nc += a.cvisits.size(), np += a.present.size();
      res.flights += a.flights;
    }
    tbb::parallel_invoke([&] { radix_sort_by_key(range_parts, ranges, ranges_tmp); },
                         [&] { radix_sort_by_key(entry_parts, entries, entries_tmp); });
    cvisits.reserve(nc), present.reserve(np);
    for (auto& a : accs) {
      cvisits.insert(cvisits.end(), a.cvisits.begin(), a.cvisits.end());
      present.insert(present.end(), a.present.begin(), a.present.end());
    }
  }
  // A total order (volume, start, flight, end): the complexity sums are then added in the same order on
  // every run, so the same request gives the same bits whatever the thread count or scheduling.
  tbb::parallel_sort(cvisits.begin(), cvisits.end(), [](const CVisit& x, const CVisit& y) {
    if (x.key != y.key) return x.key < y.key;
    if (x.a != y.a) return x.a < y.a;
    if (x.flight != y.flight) return x.flight < y.flight;
    return x.b < y.b;
  });

  // Volumes.
  res.t0 = t0, res.t1 = t1, res.step_s = r.step_s, res.duration_s = r.duration_s;
  res.entry_window_s = r.entry_window_s, res.entry_step_s = r.entry_step_s, res.method = r.method;
  res.grid = grid, res.steps = tm.K, res.entry_windows = tm.J, res.hours = tm.H;
  std::vector<std::uint64_t> keys;
  if (grid) {
    // Cells with a period range, with complexity rows, or met between periods (step > duration).
    for (std::size_t i = 0; i < ranges.size(); ++i)
      if (i == 0 || ranges[i].key != ranges[i - 1].key) keys.push_back(ranges[i].key);
    for (std::size_t i = 0; i < cvisits.size(); ++i)
      if (i == 0 || cvisits[i].key != cvisits[i - 1].key) present.push_back(cvisits[i].key);
    if (!present.empty()) {
      // Usually empty for method=samples; merged into the (already sorted) keys of the ranges.
      tbb::parallel_sort(present.begin(), present.end());
      present.erase(std::unique(present.begin(), present.end()), present.end());
      std::vector<std::uint64_t> merged;
      merged.reserve(keys.size() + present.size());
      std::set_union(keys.begin(), keys.end(), present.begin(), present.end(), std::back_inserter(merged));
      keys = std::move(merged);
    }
  } else {
    for (std::size_t i = 0; i < r.sectors.size(); ++i) keys.push_back(i);
  }
  const auto volume_of = [&](std::uint64_t key) {
    return static_cast<std::size_t>(std::lower_bound(keys.begin(), keys.end(), key) - keys.begin());
  };
  // Each volume's ranges [range_begin[v], range_begin[v + 1]) and entries likewise (every key of a
  // range or an entry is in `keys`: a sample or visit that makes an entry also makes a range or is
  // present).
  const auto begins = [&](const auto& v) {
    std::vector<std::size_t> b(keys.size() + 1);
    std::size_t i = 0;
    for (std::size_t k = 0; k < keys.size(); ++k) {
      b[k] = i;
      while (i < v.size() && v[i].key == keys[k]) ++i;
    }
    b[keys.size()] = i;
    return b;
  };
  const std::vector<std::size_t> range_begin = begins(ranges), entry_begin = begins(entries);
  if (progress) progress(0.0, "counts");

  // Each volume's description, and its occupancy and entries: the number of its index ranges holding
  // each period / window, by a difference array over the ranges' span (or, for a few ranges far apart,
  // sorted +1/-1 events). Series are built in scratch and copied once at their exact size: a grid
  // answer holds tens of thousands of them.
  struct SweepScratch {
    std::vector<std::pair<std::uint32_t, int>> ev;
    std::vector<int> diff;
    std::vector<std::uint32_t> index, value;
  };
  tbb::enumerable_thread_specific<SweepScratch> scratch;
  const auto sweep = [](SweepScratch& sc, const auto* begin, const auto* end, auto first, auto last,
                        Series& out) {
    if (begin == end) return;
    std::uint32_t lo = std::numeric_limits<std::uint32_t>::max(), hi = 0;
    std::size_t covered = 0;  // summed lengths of the ranges: at least the number of non-zero values
    for (auto* x = begin; x != end; ++x) {
      lo = std::min(lo, first(*x)), hi = std::max(hi, last(*x) + 1);
      covered += last(*x) + 1 - first(*x);
    }
    const auto n = static_cast<std::size_t>(end - begin);
    const bool dense = hi - lo <= 16 * n;
    // The values go to scratch sized for the most there can be (no per-value capacity checks), then
    // to `out` in one copy each.
    const std::size_t most = dense ? hi - lo : covered;
    if (sc.index.size() < most) sc.index.resize(most), sc.value.resize(most);
    std::size_t nz = 0;
    const auto put = [&](std::uint32_t k, int c) {
      sc.index[nz] = k, sc.value[nz] = static_cast<std::uint32_t>(c), ++nz;
    };
    if (dense) {
      // A difference array over the span: O(ranges + span), no sort.
      auto& diff = sc.diff;
      diff.assign(hi - lo + 1, 0);
      for (auto* x = begin; x != end; ++x) ++diff[first(*x) - lo], --diff[last(*x) + 1 - lo];
      int c = 0;
      for (std::uint32_t k = lo; k < hi; ++k) {
        c += diff[k - lo];
        if (c > 0) put(k, c);
      }
    } else {
      // A few ranges far apart: their sorted +1/-1 events.
      auto& ev = sc.ev;
      ev.clear();
      for (auto* x = begin; x != end; ++x) ev.push_back({first(*x), 1}), ev.push_back({last(*x) + 1, -1});
      std::sort(ev.begin(), ev.end());
      int c = 0;
      for (std::size_t e = 0; e < ev.size();) {
        const std::uint32_t at = ev[e].first;
        while (e < ev.size() && ev[e].first == at) c += ev[e++].second;
        const std::uint32_t next = e < ev.size() ? ev[e].first : at;
        if (c > 0)
          for (std::uint32_t k = at; k < next; ++k) put(k, c);
      }
    }
    out.index.assign(sc.index.begin(), sc.index.begin() + static_cast<std::ptrdiff_t>(nz));
    out.value.assign(sc.value.begin(), sc.value.begin() + static_cast<std::ptrdiff_t>(nz));
  };
  res.volumes.resize(keys.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, keys.size(), 256), [&](const auto& br) {
    SweepScratch& sc = scratch.local();
    for (std::size_t i = br.begin(); i != br.end(); ++i) {
      VolumeResult& v = res.volumes[i];
      if (grid) {
        const GridCell c = key_cell(keys[i]);
        v.id = grid_cell_id(c);
        v.is_cell = true;
        v.bounds = grid_cell_bounds(c);
        v.peak = r.peak, v.sustained = r.sustained;
      } else {
        const Sector& s = r.sectors[i];
        v.id = s.name;
        v.sector = static_cast<std::uint32_t>(i);
        v.bounds = {boxes[i].south, boxes[i].north, boxes[i].west, boxes[i].east, s.lower_m, s.upper_m};
        v.peak = s.peak ? s.peak : r.peak;
        v.sustained = s.sustained ? s.sustained : r.sustained;
      }
      sweep(
          sc, ranges.data() + range_begin[i], ranges.data() + range_begin[i + 1],
          [](const StepRange& x) { return x.k0; }, [](const StepRange& x) { return x.k1; }, v.occupancy);
      sweep(
          sc, entries.data() + entry_begin[i], entries.data() + entry_begin[i + 1],
          [](const EntryRange& x) { return x.j0; }, [](const EntryRange& x) { return x.j1; }, v.entries);
    }
  });
  std::size_t values = 0;
  for (const auto& v : res.volumes) values += v.occupancy.index.size() + v.entries.index.size();
  if (values > limits::kMaxCongestionResultValues)
    throw Error(Error::Kind::payload_too_large, too_big_param,
                "the answer would hold more than " + std::to_string(limits::kMaxCongestionResultValues) +
                    " values; narrow the window, the extent or use a longer step");
  if (cancel) cancel->throw_if_cancelled();

  // Hotspots.
  std::vector<Hotspot> hs;
  for (std::size_t vi = 0; vi < res.volumes.size(); ++vi) {
    const VolumeResult& v = res.volumes[vi];
    for (const HotspotKind kind : {HotspotKind::peak, HotspotKind::sustained}) {
      const auto thr = kind == HotspotKind::peak ? v.peak : v.sustained;
      if (!thr) continue;
      const std::size_t min_len = kind == HotspotKind::peak ? 1 : static_cast<std::size_t>(r.sustained_steps);
      const auto& idx = v.occupancy.index;
      const auto& val = v.occupancy.value;
      for (std::size_t i = 0; i < idx.size();) {
        if (!(val[i] > *thr)) {
          ++i;
          continue;
        }
        std::size_t e = i + 1;
        while (e < idx.size() && idx[e] == idx[e - 1] + 1 && val[e] > *thr) ++e;
        if (e - i >= min_len) {
          Hotspot h;
          h.volume = static_cast<std::uint32_t>(vi);
          h.kind = kind;
          h.first_step = idx[i], h.last_step = idx[e - 1];
          h.start = tm.s(h.first_step);
          h.end = std::min(tm.s(h.last_step) + r.duration_s, t1);
          for (std::size_t k = i; k < e; ++k)
            if (val[k] > h.peak) h.peak = val[k], h.peak_time = tm.s(idx[k]);
          h.threshold = *thr;
          h.excess = h.peak - *thr;
          hs.push_back(std::move(h));
        }
        i = e;
      }
    }
  }
  res.hotspots_total = hs.size();
  std::sort(hs.begin(), hs.end(), [](const Hotspot& a, const Hotspot& b) {
    if (a.excess != b.excess) return a.excess > b.excess;
    if (a.start != b.start) return a.start < b.start;
    if (a.volume != b.volume) return a.volume < b.volume;
    return a.kind < b.kind;
  });
  if (hs.size() > limits::kMaxHotspots) hs.resize(limits::kMaxHotspots);
  for (Hotspot& h : hs) {
    std::vector<std::uint32_t> ids;
    if (h.volume < keys.size()) {
      const std::uint64_t key = keys[h.volume];
      for (std::size_t i = range_begin[h.volume]; i < ranges.size() && ranges[i].key == key; ++i)
        if (ranges[i].k0 <= h.last_step && ranges[i].k1 >= h.first_step) ids.push_back(ranges[i].flight);
    }
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    for (auto id : ids) h.flights.push_back({id, flights[id].callsign, flights[id].icao24});
  }
  res.hotspots = std::move(hs);

  // Complexity.
  res.complexity_params = r.complexity_params;
  res.has_complexity = r.complexity;
  if (r.complexity) {
    if (progress) progress(0.0, "complexity");
    struct HV {
      std::uint32_t hour;
      std::uint32_t vi;  // index into cvisits
    };
    std::vector<std::size_t> starts;
    for (std::size_t i = 0; i < cvisits.size(); ++i)
      if (i == 0 || cvisits[i].key != cvisits[i - 1].key) starts.push_back(i);
    starts.push_back(cvisits.size());
    std::vector<std::vector<ComplexityCell>> per(starts.size() - 1);
    const double hcos = r.complexity_params.heading_deg, sthr = r.complexity_params.speed_kt;
    tbb::parallel_for(std::size_t(0), starts.size() - 1, [&](std::size_t g) {
      std::vector<HV> hv;
      for (std::size_t i = starts[g]; i < starts[g + 1]; ++i) {
        const auto h0 = static_cast<std::uint32_t>(std::floor((cvisits[i].a - t0) / 3600.0));
        const auto h1 = static_cast<std::uint32_t>(
            std::min<double>(tm.H - 1.0, std::floor((cvisits[i].b - t0) / 3600.0)));
        for (std::uint32_t h = h0; h <= h1; ++h) hv.push_back({h, static_cast<std::uint32_t>(i)});
      }
      std::stable_sort(hv.begin(), hv.end(), [](const HV& x, const HV& y) { return x.hour < y.hour; });
      const std::uint32_t vol = static_cast<std::uint32_t>(volume_of(cvisits[starts[g]].key));
      for (std::size_t i = 0; i < hv.size();) {
        std::size_t e = i;
        while (e < hv.size() && hv[e].hour == hv[i].hour) ++e;
        const std::uint32_t h = hv[i].hour;
        const double hs0 = t0 + 3600.0 * h, hs1 = std::min(t0 + 3600.0 * (h + 1), t1);
        ComplexityCell cell;
        cell.volume = vol, cell.hour = h;
        for (std::size_t x = i; x < e; ++x) {
          const CVisit& A = cvisits[hv[x].vi];
          const double a0 = std::max(A.a, hs0), a1 = std::min(A.b, hs1);
          if (a1 > a0) cell.flight_hours += (a1 - a0) / 3600.0;
          for (std::size_t y = x + 1; y < e; ++y) {
            const CVisit& B = cvisits[hv[y].vi];
            if (A.flight == B.flight) continue;
            const double o = std::min({A.b, B.b, hs1}) - std::max({A.a, B.a, hs0});
            if (!(o > 0)) continue;
            const double oh = o / 3600.0;
            cell.interaction_hours += oh;
            if (A.heading == A.heading && B.heading == B.heading) {
              double d = std::fabs(static_cast<double>(A.heading) - B.heading);
              if (d > 180) d = 360 - d;
              if (d > hcos) cell.horizontal_hours += oh;
            }
            if (A.attitude != B.attitude) cell.vertical_hours += oh;
            if (std::fabs(static_cast<double>(A.speed_kt) - B.speed_kt) > sthr) cell.speed_hours += oh;
          }
        }
        if (cell.flight_hours > 0) per[g].push_back(cell);
        i = e;
      }
    });
    for (auto& v : per)
      for (auto& c : v) {
        res.complexity.push_back(c);
        res.complexity_total.flight_hours += c.flight_hours;
        res.complexity_total.interaction_hours += c.interaction_hours;
        res.complexity_total.horizontal_hours += c.horizontal_hours;
        res.complexity_total.vertical_hours += c.vertical_hours;
        res.complexity_total.speed_hours += c.speed_hours;
      }
    std::sort(res.complexity.begin(), res.complexity.end(),
              [](const ComplexityCell& a, const ComplexityCell& b) {
                return a.volume != b.volume ? a.volume < b.volume : a.hour < b.hour;
              });
    values += res.complexity.size();
    if (values > limits::kMaxCongestionResultValues)
      throw Error(Error::Kind::payload_too_large, too_big_param,
                  "the answer would hold more than " + std::to_string(limits::kMaxCongestionResultValues) +
                      " values; narrow the window, the extent or use a longer step");
  }
  if (progress) progress(1.0, "complexity");
  return res;
}

}  // namespace trailscope::congestion
