#include "trailscope/congestion/congestion_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include "intervals.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/core/text.hpp"
#include "trailscope/density/colormap.hpp"
#include "trailscope/density/png.hpp"
#include "trailscope/geo/web_mercator.hpp"
#include "trailscope/trails/positions.hpp"

namespace trailscope::congestion {

namespace {

using namespace detail;

constexpr double kUnits = 4294967296.0;  // 2^32: the 32-bit Mercator grid
constexpr double kMicro = 1e6;

// The inner pixel grid of a canvas in longitude/latitude: column edges are meridians (uniform in
// longitude, unwrapped: a canvas beyond 180° has edges beyond it), row edges parallels (north to south).
struct Grid {
  int w = 0, h = 0;
  double lon0 = 0, dlon = 0;    // west edge and column width, degrees
  std::vector<double> row_lat;  // h + 1 latitudes, decreasing: row j is (row_lat[j+1], row_lat[j]]
  double north() const { return row_lat.front(); }
  double south() const { return row_lat.back(); }
  double east() const { return lon0 + dlon * w; }

  explicit Grid(const density::Canvas& full) {
    const density::Canvas c = full.inner();
    w = c.width(), h = c.height();
    const double p = static_cast<double>(c.pixel_units());
    lon0 = static_cast<double>(c.origin_x()) / kUnits * 360.0 - 180.0;
    dlon = p / kUnits * 360.0;
    row_lat.resize(static_cast<std::size_t>(h) + 1);
    for (int j = 0; j <= h; ++j)
      row_lat[static_cast<std::size_t>(j)] =
          geo::unit_y_to_lat((static_cast<double>(c.origin_y()) + p * j) / kUnits);
  }
  // Column of an unwrapped longitude inside [lon0, east()), clamped (callers pass inside values).
  int column(double lon) const {
    return std::clamp(static_cast<int>(std::floor((lon - lon0) / dlon)), 0, w - 1);
  }
  // Row of a latitude inside [south, north]: the j with row_lat[j+1] < lat <= row_lat[j].
  int row(double lat) const {
    // Edges greater than or equal to lat: row_lat is decreasing.
    const auto it =
        std::lower_bound(row_lat.begin(), row_lat.end(), lat, [](double e, double v) { return e >= v; });
    return std::clamp(static_cast<int>(it - row_lat.begin()) - 1, 0, h - 1);
  }
  // The pixel holding a position, or -1: y half-open [y_j, y_j+1) means row_lat[j+1] < lat <= row_lat[j].
  long pixel(double lat, double lon) const {
    if (!(lat <= north() && lat > south())) return -1;
    for (int k = -1; k <= 1; ++k) {
      const double l = lon + 360.0 * k;
      if (l >= lon0 && l < east()) return static_cast<long>(row(lat)) * w + column(l);
    }
    return -1;
  }
};

// Whether a flight's extents can meet the grid (a necessary condition).
bool may_meet(const Flight& f, const Grid& g) {
  if (std::isnan(f.lat_min) || f.lat_max < g.south() || f.lat_min > g.north()) return false;
  if (f.crosses_antimeridian) return true;
  for (int k = -1; k <= 1; ++k)
    if (f.lon_max + 360.0 * k >= g.lon0 && f.lon_min + 360.0 * k <= g.east()) return true;
  return false;
}

void check_mode(const Query& q, std::optional<double> t) {
  if (t) {
    if (!std::isfinite(*t)) throw invalid_argument("t", "t: the instant must be a finite time");
    if (q.t0) throw invalid_argument("t0", "t0: give either the instant t or the window t0 and t1, not both");
    if (q.t1) throw invalid_argument("t1", "t1: give either the instant t or the window t0 and t1, not both");
    return;
  }
  if (!q.t0) throw invalid_argument("t0", "t0: give the instant t, or the window t0 and t1");
  if (!q.t1) throw invalid_argument("t1", "t1: give the instant t, or the window t0 and t1");
  if (!(std::isfinite(*q.t0) && std::isfinite(*q.t1) && *q.t1 > *q.t0))
    throw invalid_argument("t1", "t1: the window must be finite with t1 > t0");
  if (*q.t1 - *q.t0 > limits::kMaxQuerySpanSeconds)
    throw invalid_argument(
        "t1", "t1: the window t1 - t0 is longer than " + format_double(limits::kMaxQuerySpanSeconds) + " s");
}

// Microseconds each flight spends in each pixel during [t0, t1), summed into `acc`.
void add_flight(const TrailSet& set, const Query& q, const Grid& g, double t0, double t1, std::uint32_t fi,
                std::vector<std::int64_t>& acc, std::vector<double>& times) {
  const PointColumns& p = set.points();
  const Flight& f = set.flights()[fi];
  const bool band = q.alt_min || q.alt_max;
  const double band_lo = q.alt_min.value_or(-std::numeric_limits<double>::infinity());
  const double band_hi = q.alt_max.value_or(std::numeric_limits<double>::infinity());
  std::vector<Iv> keep, part;
  for (std::uint32_t i = f.begin; i + 1 < f.end; ++i) {
    const double ta = p.t[i], tb = p.t[i + 1];
    const double a = std::max(ta, t0), b = std::min(tb, t1);
    if (!(b > a) || !(tb > ta)) continue;
    if (q.on_ground && (p.on_ground[i] != 0) != *q.on_ground) continue;
    const double len = b - a, dt = tb - ta, w = (a - ta) / dt;
    const double klat = (static_cast<double>(p.lat[i + 1]) - p.lat[i]) / dt;
    const double dlon = lon_step(p.lon[i], p.lon[i + 1]);
    const double klon = dlon / dt;
    const double lat0 = p.lat[i] + (static_cast<double>(p.lat[i + 1]) - p.lat[i]) * w;
    const double lon0 = p.lon[i] + dlon * w;
    keep.assign({Iv{0, len}});
    if (band) {
      if (std::isnan(p.alt[i]) || std::isnan(p.alt[i + 1])) continue;  // unknown altitude fails a band
      const double kalt = (static_cast<double>(p.alt[i + 1]) - p.alt[i]) / dt;
      intersect(keep, linear_within(p.alt[i] + kalt * (a - ta), kalt, band_lo, band_hi, len));
    }
    if (q.bbox) intersect_bbox(keep, lat0, klat, lon0, klon, *q.bbox, len);
    intersect(keep, linear_within(lat0, klat, g.south(), g.north(), len));
    if (keep.empty()) continue;
    for (int k = -1; k <= 1; ++k) {
      const double lk = lon0 + 360.0 * k;
      part = keep;
      intersect(part, linear_within(lk, klon, g.lon0, g.east(), len));
      for (const Iv& iv : part) {
        // Cut [iv.lo, iv.hi] at every column and row edge it crosses, solved from the linear motion.
        times.clear();
        times.push_back(iv.lo);
        times.push_back(iv.hi);
        const double l_lo = lk + klon * iv.lo, l_hi = lk + klon * iv.hi;
        if (klon != 0) {
          const double c_lo = std::min(l_lo, l_hi), c_hi = std::max(l_lo, l_hi);
          for (double j = std::floor((c_lo - g.lon0) / g.dlon) + 1; g.lon0 + j * g.dlon < c_hi; ++j) {
            const double x = (g.lon0 + j * g.dlon - lk) / klon;
            if (x > iv.lo && x < iv.hi) times.push_back(x);
          }
        }
        if (klat != 0) {
          const double r_lo = std::min(lat0 + klat * iv.lo, lat0 + klat * iv.hi);
          const double r_hi = std::max(lat0 + klat * iv.lo, lat0 + klat * iv.hi);
          // Row edges strictly between r_lo and r_hi (row_lat is decreasing).
          auto first = std::upper_bound(g.row_lat.begin(), g.row_lat.end(), r_hi, std::greater<double>());
          for (auto it = first; it != g.row_lat.end() && *it > r_lo; ++it) {
            const double x = (*it - lat0) / klat;
            if (x > iv.lo && x < iv.hi) times.push_back(x);
          }
        }
        std::sort(times.begin(), times.end());
        for (std::size_t m = 0; m + 1 < times.size(); ++m) {
          const double u = times[m], v = times[m + 1];
          if (!(v > u)) continue;
          const double mid = 0.5 * (u + v);
          const long px = static_cast<long>(g.row(lat0 + klat * mid)) * g.w + g.column(lk + klon * mid);
          acc[static_cast<std::size_t>(px)] += std::llround((v - u) * kMicro);
        }
      }
    }
  }
}

}  // namespace

density::Raster aircraft_per_pixel(const TrailSet& set, const Query& q, const density::Canvas& canvas,
                                   std::optional<double> t) {
  check_mode(q, t);
  const Grid g(canvas);
  density::Raster r;
  r.width = g.w, r.height = g.h;
  const std::size_t n = static_cast<std::size_t>(g.w) * static_cast<std::size_t>(g.h);
  r.values.assign(n, std::numeric_limits<float>::quiet_NaN());
  if (t) {
    // One position per flight present at t (the cap is the number of flights: never exceeded).
    const Positions at = positions_at(set, *t, q, set.num_flights());
    std::vector<std::int32_t> count(n, 0);
    for (const Position& pos : at.positions) {
      const long px = g.pixel(pos.lat, pos.lon);
      if (px >= 0) ++count[static_cast<std::size_t>(px)];
    }
    for (std::size_t i = 0; i < n; ++i)
      if (count[i] > 0) r.values[i] = static_cast<float>(count[i]);
    return r;
  }
  const double t0 = *q.t0, t1 = *q.t1;
  std::vector<std::uint32_t> flights;
  for (std::uint32_t f = 0; f < set.num_flights(); ++f)
    if (set.flights()[f].size() >= 2 && q.may_match(set.flights()[f]) && may_meet(set.flights()[f], g))
      flights.push_back(f);
  tbb::combinable<std::vector<std::int64_t>> acc([n] { return std::vector<std::int64_t>(n, 0); });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, flights.size(), 64),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      std::vector<std::int64_t>& a = acc.local();
                      std::vector<double> times;
                      for (std::size_t k = range.begin(); k != range.end(); ++k)
                        add_flight(set, q, g, t0, t1, flights[k], a, times);
                    });
  std::vector<std::int64_t> total(n, 0);
  acc.combine_each([&](const std::vector<std::int64_t>& a) {
    for (std::size_t i = 0; i < n; ++i) total[i] += a[i];
  });
  const double span_us = (t1 - t0) * kMicro;
  for (std::size_t i = 0; i < n; ++i)
    if (total[i] > 0) r.values[i] = static_cast<float>(static_cast<double>(total[i]) / span_us);
  return r;
}

void validate(const CongestionTileRequest& r, const Query& q) {
  geo::validate_tile(r.tile);
  if (r.size != limits::kTileSizeSmall && r.size != limits::kTileSizeLarge)
    throw invalid_argument("size", "size must be " + std::to_string(limits::kTileSizeSmall) + " or " +
                                       std::to_string(limits::kTileSizeLarge));
  if (!(std::isfinite(r.threshold) && r.threshold > 0))
    throw invalid_argument("threshold", "threshold: must be a finite number of aircraft > 0");
  if (r.vmax && !(std::isfinite(*r.vmax) && *r.vmax > r.threshold))
    throw invalid_argument("vmax", "vmax: must be a finite number of aircraft > threshold");
  if (r.how == density::How::eq_hist)
    throw invalid_argument("how", "how: a congestion tile is shaded 'linear' or 'log' (a fixed span)");
  density::colormap(r.cmap, "cmap");
  check_mode(q, r.t);
}

CongestionTile render_congestion_tile(const TrailSet& set, const Query& q, const CongestionTileRequest& r) {
  validate(r, q);
  const density::Canvas canvas = density::Canvas::for_tile(r.tile, r.size);
  density::Raster raster = aircraft_per_pixel(set, q, canvas, r.t);
  CongestionTile out;
  for (float& v : raster.values) {
    if (std::isnan(v)) continue;
    out.max_value = std::max(out.max_value, static_cast<double>(v));
    if (v < r.threshold)
      v = std::numeric_limits<float>::quiet_NaN();
    else
      ++out.pixels_above;
  }
  density::SpanStats span;
  span.empty = false;
  span.lo = r.threshold;
  span.hi = r.vmax.value_or(4 * r.threshold);
  density::ShadeOptions opt;
  opt.how = r.how;
  opt.cmap = r.cmap;
  out.png = density::encode_png(density::shade(raster, span, opt));
  return out;
}

}  // namespace trailscope::congestion
