#include "trailscope/trails/positions.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"
#include "trailscope/trails/partial_reads.hpp"

namespace trailscope {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

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

void validate_positions_query(double t, const Query& q) {
  if (!std::isfinite(t)) throw invalid_argument("t", "t: the instant must be a finite time");
  // An instant is not a window: say so rather than silently ignore a filter the client believes in.
  if (q.t0)
    throw invalid_argument("t0", "t0 does not apply to positions at an instant: give the instant as t");
  if (q.t1)
    throw invalid_argument("t1", "t1 does not apply to positions at an instant: give the instant as t");
}

bool position_from_samples(std::uint32_t flight_id, const PositionSample* exact, const PositionSample& a,
                           const PositionSample& b, double t, const Query& q, Position& h) {
  h.flight_id = flight_id;
  if (exact) {
    const PositionSample& e = *exact;
    h.exact = true;
    h.lat = e.lat, h.lon = e.lon;
    h.alt_m = value(e.alt), h.speed_ms = value(e.speed);
    h.track_deg = value(e.track), h.vrate_ms = value(e.vrate);
    h.on_ground = e.on_ground != 0;
  } else {
    const double w = (t - a.t) / (b.t - a.t);
    h.exact = false;
    h.lat = lerp(a.lat, b.lat, w);
    h.lon = lerp_lon(a.lon, b.lon, w);
    h.alt_m = lerp(a.alt, b.alt, w);
    h.speed_ms = lerp(a.speed, b.speed, w);
    h.track_deg = lerp_track(a.track, b.track, w);
    h.vrate_ms = lerp(a.vrate, b.vrate, w);
    h.on_ground = a.on_ground != 0;
  }
  if (q.bbox && !q.bbox->contains(h.lat, h.lon)) return false;
  if (q.alt_min || q.alt_max) {
    const double lo = q.alt_min.value_or(-std::numeric_limits<double>::infinity());
    const double hi = q.alt_max.value_or(std::numeric_limits<double>::infinity());
    if (!(h.alt_m >= lo && h.alt_m <= hi)) return false;  // NaN fails too
  }
  if (q.on_ground && h.on_ground != *q.on_ground) return false;
  return true;
}

Positions finish_positions(double t, std::vector<Position> hits, const std::vector<Flight>& flights,
                           std::size_t max_positions) {
  if (hits.size() > max_positions)
    throw Error(Error::Kind::payload_too_large, "max_positions",
                std::to_string(hits.size()) +
                    " flights match at t, more than max_positions=" + std::to_string(max_positions) +
                    "; narrow the answer with bbox, alt_min/alt_max, callsign or icao24");
  std::sort(hits.begin(), hits.end(),
            [](const Position& a, const Position& b) { return a.flight_id < b.flight_id; });
  Positions out;
  out.t = t;
  out.positions = std::move(hits);
  for (Position& p : out.positions) {
    const Flight& f = flights.at(p.flight_id);
    p.icao24 = f.icao24, p.callsign = f.callsign;
  }
  return out;
}

Positions positions_at(const TrailSet& set, double t, const Query& q, std::size_t max_positions) {
  validate_positions_query(t, q);
  const auto& pts = set.points();
  const auto& flights = set.flights();
  const auto sample = [&](std::size_t i) {
    return PositionSample{pts.t[i],     pts.lat[i],   pts.lon[i],   pts.alt[i],
                          pts.speed[i], pts.track[i], pts.vrate[i], pts.on_ground[i]};
  };
  // One flight at t, or false when it is absent or filtered out.
  const auto at = [&](std::uint32_t fi, Position& h) {
    const Flight& f = flights[fi];
    if (!(f.t_min <= t && t <= f.t_max) || f.begin == f.end) return false;
    // Without t0/t1, may_match checks the flight's position and altitude extents and its ids. The
    // interpolated values lie between their bracketing samples (for longitude: unless the flight crosses
    // 180°, which may_match knows), hence inside the extents, so a flight it rejects has no match at t.
    if (!q.may_match(f)) return false;
    const double* const first = pts.t.data() + f.begin;
    const double* const last = pts.t.data() + f.end;
    const std::size_t i = f.begin + static_cast<std::size_t>(std::lower_bound(first, last, t) - first);
    if (pts.t[i] == t) {
      const PositionSample e = sample(i);
      return position_from_samples(fi, &e, e, e, t, q, h);
    }
    // f.t_min <= t < pts.t[i], so i > f.begin and pts.t[i - 1] < t < pts.t[i].
    return position_from_samples(fi, nullptr, sample(i - 1), sample(i), t, q, h);
  };
  // Chunks of flights in parallel; the reduction joins left to right (TBB's parallel_reduce does not
  // need a commutative join), so hits stay in flight order.
  std::vector<Position> hits = tbb::parallel_reduce(
      tbb::blocked_range<std::uint32_t>(0, static_cast<std::uint32_t>(flights.size()), 256),
      std::vector<Position>(),
      [&](const tbb::blocked_range<std::uint32_t>& r, std::vector<Position> acc) {
        Position h;
        for (std::uint32_t fi = r.begin(); fi != r.end(); ++fi)
          if (at(fi, h)) acc.push_back(h);
        return acc;
      },
      [](std::vector<Position> a, const std::vector<Position>& b) {
        a.insert(a.end(), b.begin(), b.end());
        return a;
      });
  return finish_positions(t, std::move(hits), flights, max_positions);
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
