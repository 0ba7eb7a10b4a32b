#include "trailscope/trails/positions.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"

namespace trailscope {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The numbers of one hit; names are copied only once the count is known to be within the cap.
struct Hit {
  std::uint32_t flight = 0;
  double lat = 0, lon = 0, alt = 0, speed = 0, track = 0, vrate = 0;
  bool on_ground = false, exact = false;
};

// a + (b - a)·w, unknown when either end is.
double lerp(float a, float b, double w) {
  if (a != a || b != b) return kNaN;
  return a + (static_cast<double>(b) - a) * w;
}

// Longitude the shortest way round, into [-180, 180). Whether to go across 180° is decided by the test
// compute_extents() uses for Flight::crosses_antimeridian (|Δlon| > 180° in float; exactly 180° goes the
// plain way), so a flight without that flag never leaves its [lon_min, lon_max] extent between samples
// and the zone map in positions_at() stays exact.
double lerp_lon(float a, float b, double w) {
  double d = static_cast<double>(b) - a;
  if (std::fabs(b - a) > 180.0f) d += d > 0 ? -360.0 : 360.0;
  double lon = a + d * w;
  if (lon >= 180) lon -= 360;
  if (lon < -180) lon += 360;
  if (lon >= 180) lon = -180;  // -180 - ε + 360 rounds to 180
  return lon;
}

// Track by the shortest arc, into [0, 360); tracks exactly 180° apart turn clockwise.
double lerp_track(float a, float b, double w) {
  if (a != a || b != b) return kNaN;
  double d = static_cast<double>(b) - a;
  d = std::fmod(d, 360.0);  // tracks outside [0, 360) are tolerated
  if (d > 180)
    d -= 360;
  else if (d <= -180)
    d += 360;
  double tr = std::fmod(a + d * w, 360.0);
  if (tr < 0) tr += 360;
  if (tr >= 360) tr = 0;  // -ε + 360 rounds to 360
  return tr;
}

double value(float v) {
  return v == v ? static_cast<double>(v) : kNaN;
}

nlohmann::json properties(const Position& p) {
  return {{"id", p.flight_id},
          {"icao24", p.icao24},
          {"callsign", p.callsign},
          {"lat", p.lat},
          {"lon", p.lon},
          {"alt_m", number_or_null(p.alt_m)},
          {"speed_ms", number_or_null(p.speed_ms)},
          {"track_deg", number_or_null(p.track_deg)},
          {"vrate_ms", number_or_null(p.vrate_ms)},
          {"on_ground", p.on_ground},
          {"exact", p.exact}};
}
}  // namespace

Positions positions_at(const TrailSet& set, double t, const Query& q, std::size_t max_positions) {
  if (!std::isfinite(t)) throw invalid_argument("t", "t: the instant must be a finite time");
  // An instant is not a window: say so rather than silently ignore a filter the client believes in.
  if (q.t0)
    throw invalid_argument("t0", "t0 does not apply to positions at an instant: give the instant as t");
  if (q.t1)
    throw invalid_argument("t1", "t1 does not apply to positions at an instant: give the instant as t");
  const auto& pts = set.points();
  const auto& flights = set.flights();
  const bool has_alt = q.alt_min || q.alt_max;
  const double alt_lo = q.alt_min.value_or(-std::numeric_limits<double>::infinity());
  const double alt_hi = q.alt_max.value_or(std::numeric_limits<double>::infinity());

  // One flight at t, or false when it is absent or filtered out.
  const auto at = [&](std::uint32_t fi, Hit& h) {
    const Flight& f = flights[fi];
    if (!(f.t_min <= t && t <= f.t_max) || f.begin == f.end) return false;
    // Without t0/t1, may_match checks the flight's position and altitude extents and its ids. The
    // interpolated values lie between their bracketing samples (for longitude: unless the flight crosses
    // 180°, which may_match knows), hence inside the extents, so a flight it rejects has no match at t.
    if (!q.may_match(f)) return false;
    const double* const first = pts.t.data() + f.begin;
    const double* const last = pts.t.data() + f.end;
    const std::size_t i = f.begin + static_cast<std::size_t>(std::lower_bound(first, last, t) - first);
    h.flight = fi;
    if (pts.t[i] == t) {
      h.exact = true;
      h.lat = pts.lat[i], h.lon = pts.lon[i];
      h.alt = value(pts.alt[i]), h.speed = value(pts.speed[i]);
      h.track = value(pts.track[i]), h.vrate = value(pts.vrate[i]);
      h.on_ground = pts.on_ground[i] != 0;
    } else {
      // f.t_min <= t < pts.t[i], so i > f.begin and pts.t[i - 1] < t < pts.t[i].
      const std::size_t a = i - 1, b = i;
      const double w = (t - pts.t[a]) / (pts.t[b] - pts.t[a]);
      h.exact = false;
      h.lat = lerp(pts.lat[a], pts.lat[b], w);
      h.lon = lerp_lon(pts.lon[a], pts.lon[b], w);
      h.alt = lerp(pts.alt[a], pts.alt[b], w);
      h.speed = lerp(pts.speed[a], pts.speed[b], w);
      h.track = lerp_track(pts.track[a], pts.track[b], w);
      h.vrate = lerp(pts.vrate[a], pts.vrate[b], w);
      h.on_ground = pts.on_ground[a] != 0;
    }
    if (q.bbox && !q.bbox->contains(h.lat, h.lon)) return false;
    if (has_alt && !(h.alt >= alt_lo && h.alt <= alt_hi)) return false;  // NaN fails too
    if (q.on_ground && h.on_ground != *q.on_ground) return false;
    return true;
  };

  // Chunks of flights in parallel; the reduction joins left to right (TBB's parallel_reduce does not
  // need a commutative join), so hits stay in flight order.
  std::vector<Hit> hits = tbb::parallel_reduce(
      tbb::blocked_range<std::uint32_t>(0, static_cast<std::uint32_t>(flights.size()), 256),
      std::vector<Hit>(),
      [&](const tbb::blocked_range<std::uint32_t>& r, std::vector<Hit> acc) {
        Hit h;
        for (std::uint32_t fi = r.begin(); fi != r.end(); ++fi)
          if (at(fi, h)) acc.push_back(h);
        return acc;
      },
      [](std::vector<Hit> a, const std::vector<Hit>& b) {
        a.insert(a.end(), b.begin(), b.end());
        return a;
      });
  if (hits.size() > max_positions)
    throw Error(Error::Kind::payload_too_large, "max_positions",
                std::to_string(hits.size()) +
                    " flights match at t, more than max_positions=" + std::to_string(max_positions) +
                    "; narrow the answer with bbox, alt_min/alt_max, callsign or icao24");
  std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) { return a.flight < b.flight; });

  Positions out;
  out.t = t;
  out.positions.reserve(hits.size());
  for (const Hit& h : hits) {
    const Flight& f = flights[h.flight];
    Position p;
    p.flight_id = h.flight;
    p.icao24 = f.icao24, p.callsign = f.callsign;
    p.lat = h.lat, p.lon = h.lon, p.alt_m = h.alt;
    p.speed_ms = h.speed, p.track_deg = h.track, p.vrate_ms = h.vrate;
    p.on_ground = h.on_ground, p.exact = h.exact;
    out.positions.push_back(std::move(p));
  }
  return out;
}

nlohmann::json Positions::to_json() const {
  nlohmann::json list = nlohmann::json::array();
  for (const Position& p : positions) list.push_back(properties(p));
  return {{"t", t}, {"count", positions.size()}, {"positions", std::move(list)}};
}

nlohmann::json Positions::to_geojson() const {
  nlohmann::json features = nlohmann::json::array();
  for (const Position& p : positions) {
    nlohmann::json props = properties(p);
    props.erase("lat");
    props.erase("lon");
    features.push_back({{"type", "Feature"},
                        {"id", p.flight_id},
                        {"geometry", {{"type", "Point"}, {"coordinates", {p.lon, p.lat}}}},
                        {"properties", std::move(props)}});
  }
  return {{"type", "FeatureCollection"},
          {"t", t},
          {"count", positions.size()},
          {"features", std::move(features)}};
}

}  // namespace trailscope
