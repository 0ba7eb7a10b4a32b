// Animation chunks (TSAN, proto/animation_chunks.md), checked against computations written here that share
// no code with compute/src/trails/animation_chunk.cpp or server/src/formats/animation_chunk.cpp:
//   - a decoder of the documented layout (offsets, padding, flight table, columns);
//   - a brute-force selection (a scan over every point of every flight, no zone map, no binary search);
//   - the documented client rule (x linear, the short way across 180°; latitude linear in degrees via
//     y → lat → lerp; attributes linear, track by the shortest arc), which must reproduce positions_at()
//     (compute/.../trails/positions.hpp) at every instant of a chunk: the same flights, positions within
//     1 m, the attributes equal. The bound is the float32 rounding of x and y relative to the origin
//     (2^-24·|x|: 0.2 m at 3,000 km) and of latitude in float (~0.4 m).
// Then the route: bytes, ETag, 304, cache, and every refusal with its exact status and message.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "formats/animation_chunk.hpp"
#include "route_fixture.hpp"
#include "trailscope/ingest/ingest.hpp"
#include "trailscope/trails/animation_chunk.hpp"
#include "trailscope/trails/positions.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::server {
namespace {

constexpr double kR = 6378137.0;
constexpr double kPi = 3.14159265358979323846;
constexpr double kDay = 1514764800.0;  // 2018-01-01T00:00:00Z
constexpr double kMaxLat = 85.051128779806592;

// --- an independent TSAN decoder -------------------------------------------------------------------
struct Decoded {
  double t_start = 0, duration = 0, ox = 0, oy = 0;
  struct F {
    std::uint32_t id, first, count, icao;
    std::string callsign;
  };
  std::vector<F> flights;
  std::vector<float> t, x, y, alt, speed, track, vrate;
  std::vector<std::uint8_t> ground;
};

template <typename T>
T read_at(const std::string& b, std::size_t off) {
  EXPECT_LE(off + sizeof(T), b.size());
  T v{};
  if (off + sizeof(T) <= b.size()) std::memcpy(&v, b.data() + off, sizeof(T));
  return v;
}

Decoded decode(const std::string& b) {
  Decoded d;
  EXPECT_GE(b.size(), 64u);
  EXPECT_EQ(b.substr(0, 4), "TSAN");
  EXPECT_EQ(read_at<std::uint16_t>(b, 4), 1);
  EXPECT_EQ(read_at<std::uint16_t>(b, 6), 0);
  d.t_start = read_at<double>(b, 8);
  d.duration = read_at<double>(b, 16);
  d.ox = read_at<double>(b, 24);
  d.oy = read_at<double>(b, 32);
  const std::size_t F = read_at<std::uint32_t>(b, 40), N = read_at<std::uint32_t>(b, 44);
  const std::size_t S = read_at<std::uint32_t>(b, 48);
  EXPECT_EQ(read_at<std::uint32_t>(b, 52), 0u);
  EXPECT_EQ(read_at<double>(b, 56), 0.0);
  const auto pad = [](std::size_t n) { return (n + 7) / 8 * 8; };
  const std::size_t C = pad(4 * N), cols = 64 + 24 * F, strings = cols + 7 * C + pad(N);
  EXPECT_EQ(b.size(), strings + pad(S)) << "total size";
  if (b.size() != strings + pad(S)) return d;
  std::uint32_t expect_first = 0;
  for (std::size_t i = 0; i < F; ++i) {
    const std::size_t r = 64 + 24 * i;
    Decoded::F f{read_at<std::uint32_t>(b, r),
                 read_at<std::uint32_t>(b, r + 4),
                 read_at<std::uint32_t>(b, r + 8),
                 read_at<std::uint32_t>(b, r + 12),
                 {}};
    const std::uint32_t off = read_at<std::uint32_t>(b, r + 16), len = read_at<std::uint32_t>(b, r + 20);
    EXPECT_LE(off + len, S);
    f.callsign = b.substr(strings + off, len);
    EXPECT_EQ(f.first, expect_first) << "samples of the flights follow each other";
    EXPECT_GE(f.count, 1u);
    expect_first += f.count;
    if (i) EXPECT_LT(d.flights.back().id, f.id) << "ordered by flight id";
    d.flights.push_back(std::move(f));
  }
  EXPECT_EQ(expect_first, N);
  const auto col = [&](int k) {
    std::vector<float> v(N);
    if (N) std::memcpy(v.data(), b.data() + cols + k * C, 4 * N);
    return v;
  };
  d.t = col(0), d.x = col(1), d.y = col(2), d.alt = col(3), d.speed = col(4), d.track = col(5),
  d.vrate = col(6);
  d.ground.assign(b.begin() + static_cast<std::ptrdiff_t>(cols + 7 * C),
                  b.begin() + static_cast<std::ptrdiff_t>(cols + 7 * C + N));
  // Padding is zero.
  for (std::size_t k = 0; k < 7; ++k)
    for (std::size_t i = cols + k * C + 4 * N; i < cols + (k + 1) * C; ++i) EXPECT_EQ(b[i], 0);
  for (std::size_t i = cols + 7 * C + N; i < strings; ++i) EXPECT_EQ(b[i], 0);
  return d;
}

// --- the documented client rule ----------------------------------------------------------------------
struct Drawn {
  std::uint32_t id = 0;
  double lat = 0, lon = 0, alt = 0, speed = 0, track = 0, vrate = 0;
  bool ground = false;
  double x_span = 0;  ///< the largest |x| (relative to the origin) of the samples used
};

double y_to_lat(double y_abs) {
  return std::atan(std::sinh(y_abs / kR)) * 180 / kPi;
}
double norm_lon(double lon) {
  while (lon >= 180) lon -= 360;
  while (lon < -180) lon += 360;
  return lon;
}
double lin(float a, float b, double w) {
  if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<double>::quiet_NaN();
  return a + (double(b) - a) * w;
}

std::vector<Drawn> draw(const Decoded& d, double instant) {
  const double u = instant - d.t_start;
  std::vector<Drawn> out;
  for (const auto& f : d.flights) {
    const std::size_t lo = f.first, hi = f.first + f.count;
    if (!(d.t[lo] <= u && u <= d.t[hi - 1])) continue;
    std::size_t k = lo;
    while (d.t[k] < u) ++k;
    Drawn p;
    p.id = f.id;
    if (d.t[k] == u) {
      p.lon = norm_lon((d.x[k] + d.ox) / kR * 180 / kPi);
      p.lat = y_to_lat(d.y[k] + d.oy);
      p.alt = d.alt[k], p.speed = d.speed[k], p.track = d.track[k], p.vrate = d.vrate[k];
      p.ground = d.ground[k];
      p.x_span = std::fabs(d.x[k]);
    } else {
      const std::size_t a = k - 1, b = k;
      const double w = (u - d.t[a]) / (double(d.t[b]) - d.t[a]);
      double xb = d.x[b];
      if (std::fabs(xb - d.x[a]) > kPi * kR) xb += xb > d.x[a] ? -2 * kPi * kR : 2 * kPi * kR;
      p.lon = norm_lon((d.x[a] + (xb - d.x[a]) * w + d.ox) / kR * 180 / kPi);
      const double la = y_to_lat(d.y[a] + d.oy), lb = y_to_lat(d.y[b] + d.oy);
      p.lat = la + (lb - la) * w;
      p.alt = lin(d.alt[a], d.alt[b], w), p.speed = lin(d.speed[a], d.speed[b], w);
      p.vrate = lin(d.vrate[a], d.vrate[b], w);
      if (std::isnan(d.track[a]) || std::isnan(d.track[b])) {
        p.track = std::numeric_limits<double>::quiet_NaN();
      } else {
        double dt = std::fmod(double(d.track[b]) - d.track[a] + 540.0, 360.0) - 180.0;  // (-180, 180]
        if (dt == -180) dt = 180;                                                       // clockwise
        p.track = std::fmod(d.track[a] + dt * w + 360.0, 360.0);
      }
      p.ground = d.ground[a];
      p.x_span = std::max(std::fabs(d.x[a]), std::fabs(d.x[b]));
    }
    out.push_back(p);
  }
  return out;
}

double metres_apart(double lat1, double lon1, double lat2, double lon2) {
  const double r = kPi / 180, dlat = (lat2 - lat1) * r, dlon = (lon2 - lon1) * r;
  const double h = std::sin(dlat / 2) * std::sin(dlat / 2) +
                   std::cos(lat1 * r) * std::cos(lat2 * r) * std::sin(dlon / 2) * std::sin(dlon / 2);
  return 2 * 6371008.8 * std::asin(std::min(1.0, std::sqrt(h)));
}

void expect_same_value(double a, double b, const char* what, std::uint32_t id) {
  if (std::isnan(a) || std::isnan(b)) {
    EXPECT_EQ(std::isnan(a), std::isnan(b)) << what << " of flight " << id;
    return;
  }
  EXPECT_NEAR(a, b, 1e-6 * std::max(1.0, std::fabs(b))) << what << " of flight " << id;
}

// positions_at(set, instant) against the chunk containing it, drawn with the client rule. Returns the
// number of flights compared; `worst` gets the largest distance.
std::size_t expect_chunk_matches_positions(const TrailSet& set, double instant, double duration,
                                           double* worst) {
  const double start = std::floor(instant / duration) * duration;
  const AnimationOrigin origin = default_animation_origin(set);
  const AnimationChunk chunk = animation_chunk(set, start, duration, Query{}, 50'000'000);
  const Decoded d = decode(encode_animation_chunk(set, chunk, origin));
  const std::vector<Drawn> drawn = draw(d, instant);
  const Positions at = positions_at(set, instant, Query{}, 10'000'000);
  EXPECT_EQ(drawn.size(), at.positions.size()) << "flights at " << std::to_string(instant);
  if (drawn.size() != at.positions.size()) return 0;
  for (std::size_t i = 0; i < drawn.size(); ++i) {
    const Drawn& p = drawn[i];
    const Position& q = at.positions[i];
    EXPECT_EQ(p.id, q.flight_id);
    const double m = metres_apart(p.lat, p.lon, q.lat, q.lon);
    *worst = std::max(*worst, m);
    // To the metre; beyond 2^24 m (16,777 km) from the origin a float32 step of x is 2 m, so there
    // (the far side of a world-wide set) half a step more.
    const double limit = std::max(1.0, 0.5 + std::ldexp(p.x_span, -24));
    EXPECT_LT(m, limit) << "flight " << q.flight_id << " at " << std::to_string(instant) << ": (" << p.lat
                        << ", " << p.lon << ") vs (" << q.lat << ", " << q.lon << ")";
    expect_same_value(p.alt, q.alt_m, "alt", q.flight_id);
    expect_same_value(p.speed, q.speed_ms, "speed", q.flight_id);
    expect_same_value(p.vrate, q.vrate_ms, "vrate", q.flight_id);
    if (!std::isnan(p.track) && !std::isnan(q.track_deg)) {
      const double dtr = std::fabs(p.track - q.track_deg);
      EXPECT_LT(std::min(dtr, 360 - dtr), 1e-6) << "track of flight " << q.flight_id;
    } else {
      EXPECT_EQ(std::isnan(p.track), std::isnan(q.track_deg)) << "track of flight " << q.flight_id;
    }
    EXPECT_EQ(p.ground, q.on_ground) << "on_ground of flight " << q.flight_id;
  }
  return drawn.size();
}

// The brute-force selection and the decoded chunk sample by sample: the same flights, the same samples
// (times within 1 ms after float32, positions within half a float32 step, attributes bit-equal).
std::size_t expect_selection(const TrailSet& set, double start, double duration,
                             const std::string& callsign = "") {
  const AnimationOrigin origin = default_animation_origin(set);
  Query q;
  q.callsign = callsign;
  const Decoded d =
      decode(encode_animation_chunk(set, animation_chunk(set, start, duration, q, 50'000'000), origin));
  const double ox = kR * origin.lon * kPi / 180;
  const double oy = kR * std::asinh(std::tan(std::clamp(origin.lat, -kMaxLat, kMaxLat) * kPi / 180));
  EXPECT_EQ(d.t_start, start);
  EXPECT_EQ(d.duration, duration);
  EXPECT_DOUBLE_EQ(d.ox, ox);
  EXPECT_DOUBLE_EQ(d.oy, oy);
  const auto& pts = set.points();
  std::size_t fi_dec = 0, checked = 0;
  double worst_t = 0;
  for (std::uint32_t fi = 0; fi < set.num_flights(); ++fi) {
    const Flight& f = set.flights()[fi];
    if (!callsign.empty() && f.callsign.rfind(callsign, 0) != 0) continue;
    std::vector<std::uint32_t> want;
    std::int64_t before = -1, after = -1;
    for (std::uint32_t p = f.begin; p < f.end; ++p) {
      if (pts.t[p] >= start && pts.t[p] < start + duration) want.push_back(p);
      if (pts.t[p] < start) before = p;  // time-sorted: the last one wins
      if (pts.t[p] >= start + duration && after < 0) after = p;
    }
    const bool present = f.end > f.begin && pts.t[f.begin] < start + duration && pts.t[f.end - 1] >= start;
    if (!present) continue;
    if (before >= 0) want.insert(want.begin(), static_cast<std::uint32_t>(before));
    if (after >= 0) want.push_back(static_cast<std::uint32_t>(after));
    if (fi_dec >= d.flights.size()) {
      ADD_FAILURE() << "flight " << fi << " missing";
      return 0;
    }
    const auto& g = d.flights[fi_dec++];
    EXPECT_EQ(g.id, fi);
    EXPECT_EQ(g.count, want.size()) << "samples of flight " << fi;
    if (g.id != fi || g.count != want.size()) return 0;
    checked += want.size();
    EXPECT_EQ(g.callsign, f.callsign);
    EXPECT_EQ(g.icao, f.icao24.empty() ? 0xFFFFFFFFu : std::stoul(f.icao24, nullptr, 16));
    for (std::size_t k = 0; k < want.size(); ++k) {
      const std::uint32_t p = want[k];
      const std::size_t s = g.first + k;
      const double dt = std::fabs(d.t_start + double(d.t[s]) - pts.t[p]);
      worst_t = std::max(worst_t, dt);
      const double x = kR * double(pts.lon[p]) * kPi / 180 - ox;
      const double y =
          kR * std::asinh(std::tan(std::clamp(double(pts.lat[p]), -kMaxLat, kMaxLat) * kPi / 180)) - oy;
      EXPECT_LE(std::fabs(d.x[s] - x), std::ldexp(std::fabs(x), -24) + 1e-9);
      EXPECT_LE(std::fabs(d.y[s] - y), std::ldexp(std::fabs(y), -24) + 1e-9);
      const auto bits_eq = [](float a, float b) { return (std::isnan(a) && std::isnan(b)) || a == b; };
      EXPECT_TRUE(bits_eq(d.alt[s], pts.alt[p]));
      EXPECT_TRUE(bits_eq(d.speed[s], pts.speed[p]));
      EXPECT_TRUE(bits_eq(d.track[s], pts.track[p]));
      EXPECT_TRUE(bits_eq(d.vrate[s], pts.vrate[p]));
      EXPECT_EQ(d.ground[s], pts.on_ground[p]);
    }
  }
  EXPECT_EQ(fi_dec, d.flights.size()) << "extra flights in the chunk";
  EXPECT_LT(worst_t, 1e-3) << "float32 relative times";
  return checked;
}

// --- a synthetic set: random legs, fractional (quarter-second) times, unknown values, 180° crossings ---
TrailSet synthetic(std::uint64_t seed, int aircraft) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u01(0, 1);
  TrailSetBuilder b;
  for (int a = 0; a < aircraft; ++a) {
    char icao[7];
    std::snprintf(icao, sizeof icao, "%06x", 0x400000 + a);
    const std::string cs = (a % 3 ? "TST" : "ABC") + std::to_string(a);
    const bool dateline = a % 7 == 0;
    double t = kDay + std::round(u01(rng) * 80000 * 4) / 4;
    double lat = dateline ? -50 + 100 * u01(rng) : 35 + 30 * u01(rng);
    double lon = dateline ? 179 + 2 * u01(rng) : -10 + 40 * u01(rng);
    if (lon >= 180) lon -= 360;
    const double heading = u01(rng) * 360;
    const int n = 2 + static_cast<int>(u01(rng) * 200);
    for (int i = 0; i < n; ++i) {
      Sample s;
      s.t = t, s.lat = static_cast<float>(lat), s.lon = static_cast<float>(lon);
      s.alt = i % 11 == 5 ? Sample::kUnknown : static_cast<float>(10000 * u01(rng));
      s.speed = static_cast<float>(250 * u01(rng));
      s.track =
          i % 13 == 7 ? Sample::kUnknown : static_cast<float>(std::fmod(heading + 40 * u01(rng), 360.0));
      s.vrate = static_cast<float>(20 * u01(rng) - 10);
      s.on_ground = i < 2;
      b.add(icao, cs, s);
      t += std::round((1 + 600 * u01(rng) * u01(rng)) * 4) / 4;  // now and then longer than a chunk
      lat = std::clamp(lat + (u01(rng) - 0.5) * 0.5, -84.0, 84.0);
      lon += dateline ? 0.3 * (u01(rng) - 0.2) : (u01(rng) - 0.5) * 0.5;
      if (lon >= 180) lon -= 360;
      if (lon < -180) lon += 360;
    }
  }
  return b.build();
}

std::vector<double> instants(double day, std::uint64_t seed, int n) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 86400);
  std::vector<double> v = {day + 86000, day + 86000.5, day + 86399.75,
                           day + 86100, day + 3600,    day + 43210.123};
  for (int i = 0; i < n; ++i) v.push_back(day + u(rng));
  return v;
}

TEST(AnimationChunk, SyntheticSetDrawnWithTheClientRuleIsPositionsAt) {
  const TrailSet set = synthetic(7, 600);
  std::size_t compared = 0;
  double worst = 0;
  for (const double duration : {10.0, 300.0, 3600.0})
    for (const double instant : instants(kDay, 11, 30))
      compared += expect_chunk_matches_positions(set, instant, duration, &worst);
  EXPECT_GT(compared, 3000u);
  std::printf("synthetic: %zu positions compared, worst %.3f m\n", compared, worst);
}

TEST(AnimationChunk, SyntheticSelectionIsTheBruteForceOne) {
  const TrailSet set = synthetic(8, 300);
  std::size_t checked = 0;
  for (const double duration : {10.0, 300.0, 3600.0})
    for (const double instant : instants(kDay, 12, 6))
      checked += expect_selection(set, std::floor(instant / duration) * duration, duration);
  EXPECT_GT(checked, 5000u);
  EXPECT_GT(expect_selection(set, kDay + 36000, 3600, "ABC"), 10u);  // a flight-level filter
}

// Edges: a flight present only at the chunk's end instant is not in it (half-open) but one that ends at
// its start is; bracketing samples; a leg longer than the chunk; 180°; single-sample flights.
TrailSet boundaries_set() {
  TrailSetBuilder b;
  const auto add = [&](const char* icao, const char* cs, double t, float lat, float lon) {
    Sample s;
    s.t = t, s.lat = lat, s.lon = lon, s.alt = 1000, s.speed = 100, s.track = 90, s.vrate = 0;
    b.add(icao, cs, s);
  };
  const double T = kDay + 600, S = 300;
  add("000001", "STARTS", T + S, 50, 5);  // starts exactly at the chunk's end: next chunk only
  add("000001", "STARTS", T + S + 60, 50, 6);
  add("000002", "ENDS", T - 120, 51, 5);  // ends exactly at the chunk start: present at T
  add("000002", "ENDS", T, 51, 6);
  add("000003", "SPANS", T - 500, 52, 5);  // one leg over the whole chunk: two bracketing samples
  add("000003", "SPANS", T + S + 500, 60, 7);
  add("000004", "INSIDE", T - 30, 53, 5);  // samples inside plus one each side (not -30 nor 320)
  add("000004", "INSIDE", T - 10, 53.5f, 5.1f);
  add("000004", "INSIDE", T + 100, 55, 5.2f);
  add("000004", "INSIDE", T + 299.75, 58, 5.3f);
  add("000004", "INSIDE", T + 310, 58.5f, 5.4f);
  add("000004", "INSIDE", T + 320, 59, 5.5f);
  add("000005", "DATELINE", T + 10, 10, 179.9f);  // crosses 180° eastwards inside the chunk
  add("000005", "DATELINE", T + 70, 12, -179.9f);
  add("000006", "BEFORE", T - 1000, 40, 0);  // entirely before
  add("000006", "BEFORE", T - 1, 40, 1);
  add("000007", "SINGLE", T + 150, 45, 10);  // one sample
  return b.build();
}

TEST(AnimationChunk, ChunkBoundaries) {
  const double T = kDay + 600, S = 300;
  const TrailSet set = boundaries_set();
  const AnimationChunk c = animation_chunk(set, T, S, Query{}, 1000);
  std::vector<std::string> names;
  for (const auto& f : c.flights)
    names.push_back(set.flights()[f.flight_id].callsign + ":" + std::to_string(f.size()));
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"DATELINE:2", "ENDS:2", "INSIDE:4", "SINGLE:1", "SPANS:2"}));
  EXPECT_EQ(c.samples, 11u);
  EXPECT_EQ(expect_selection(set, T, S), 11u);
  // The next chunk has STARTS and INSIDE's last samples (310 is its first at or after T+S, 320 follows).
  EXPECT_EQ(expect_selection(set, T + S, S), 7u);  // STARTS 2, INSIDE 3 (299.75 before, 310, 320), SPANS 2
  double worst = 0;
  for (double u : {0.0, 0.5, 10.0, 40.0, 69.75, 150.0, 299.75, 299.999})
    expect_chunk_matches_positions(set, T + u, S, &worst);
  // Across 180°: the client's x goes the short way, so at the middle the flight is at 180°, not 0°.
  const Decoded d = decode(encode_animation_chunk(set, c, default_animation_origin(set)));
  for (const Drawn& p : draw(d, T + 40))
    if (set.flights()[p.id].callsign == "DATELINE") EXPECT_NEAR(std::fabs(p.lon), 180.0, 1e-4);
  // The sample cap counts bracketing samples, before anything is built.
  try {
    animation_chunk(set, T, S, Query{}, 10);
    ADD_FAILURE() << "no 413";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::payload_too_large);
    EXPECT_EQ(e.param(), "duration");
    EXPECT_STREQ(
        e.what(),
        "the chunk holds 11 samples, more than 10; ask for a shorter duration or filter by callsign or "
        "icao24");
  }
}

// A small chunk and positions_at()'s answers inside it, for decoders in other languages (the browser's):
// tests/golden/anim_boundaries.tsan is the chunk [T, T+300) of boundaries_set(), and
// tests/golden/anim_boundaries.json holds {"chunk": {t, duration}, "instants": [{"t", "positions"}]} with
// the positions' JSON (compute/.../trails/positions.hpp). Written by this test with
// TRAILSCOPE_UPDATE_GOLDEN=1, compared byte for byte otherwise.
TEST(AnimationChunk, GoldenForDecoders) {
  const double T = kDay + 600, S = 300;
  const TrailSet set = boundaries_set();
  const std::string bytes =
      encode_animation_chunk(set, animation_chunk(set, T, S, Query{}, 1000), default_animation_origin(set));
  nlohmann::json instants = nlohmann::json::array();
  for (double u : {0.0, 0.5, 10.0, 40.0, 69.75, 150.0, 299.75}) {
    const Positions at = positions_at(set, T + u, Query{}, 1000);
    instants.push_back({{"t", T + u}, {"positions", at.to_json()["positions"]}});
  }
  const std::string json =
      nlohmann::json{{"chunk", {{"t", T}, {"duration", S}}}, {"instants", instants}}.dump(1) + "\n";
  const auto dir = test::source_dir() / "tests" / "golden";
  if (const char* u = std::getenv("TRAILSCOPE_UPDATE_GOLDEN"); u && std::string(u) == "1") {
    std::ofstream(dir / "anim_boundaries.tsan", std::ios::binary) << bytes;
    std::ofstream(dir / "anim_boundaries.json", std::ios::binary) << json;
    std::printf("wrote %s/anim_boundaries.{tsan,json}\n", dir.c_str());
    return;
  }
  const auto slurp = [](const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  ASSERT_TRUE(std::filesystem::exists(dir / "anim_boundaries.tsan"))
      << "TRAILSCOPE_UPDATE_GOLDEN=1 writes it";
  EXPECT_EQ(slurp(dir / "anim_boundaries.tsan"), bytes);
  EXPECT_EQ(slurp(dir / "anim_boundaries.json"), json);
  // And the golden positions are what the client rule gives from the golden chunk.
  double worst = 0;
  for (const auto& i : instants)
    EXPECT_GT(expect_chunk_matches_positions(set, i["t"].get<double>(), S, &worst), 0u);
}

// --- the Europe SO6 day ----------------------------------------------------------------------------
std::filesystem::path so6_path() {
  return test::shared_data("flights/traffic_europe_20180101_m3.so6.gz");
}
const TrailSet& europe() {
  static const TrailSet set = ingest::ingest_file(so6_path().string());
  return set;
}

TEST(AnimationChunkEurope, DrawnWithTheClientRuleIsPositionsAtToTheMetre) {
  if (!std::filesystem::exists(so6_path())) GTEST_SKIP() << so6_path() << " is absent";
  const TrailSet& set = europe();
  std::size_t compared = 0;
  double worst = 0;
  for (const double duration : {60.0, 300.0})
    for (const double instant : instants(kDay, 21, 25))
      compared += expect_chunk_matches_positions(set, instant, duration, &worst);
  EXPECT_GT(compared, 40000u);
  std::printf("Europe day: %zu positions compared, worst %.3f m\n", compared, worst);
}

TEST(AnimationChunkEurope, SelectionIsTheBruteForceOne) {
  if (!std::filesystem::exists(so6_path())) GTEST_SKIP() << so6_path() << " is absent";
  std::size_t checked = 0;
  for (const double start : {kDay, kDay + 8 * 3600, kDay + 86100})
    checked += expect_selection(europe(), start, 300);
  checked += expect_selection(europe(), kDay + 12 * 3600, 3600);
  EXPECT_GT(checked, 10000u);
  std::printf("Europe day (%zu flights, %zu points): %zu samples checked\n", europe().num_flights(),
              europe().num_points(), checked);
}

// --- the route ---------------------------------------------------------------------------------------
std::shared_ptr<Dataset> dataset(const std::string& id, TrailSet set) {
  auto ds = std::make_shared<Dataset>();
  ds->id = id, ds->name = id, ds->format = "test", ds->created = "2026-01-01T00:00:00Z";
  ds->trails = std::make_shared<const TrailSet>(std::move(set));
  return ds;
}

class AnimationRoute : public test_routes::RouteFixture {
 protected:
  AnimationRoute() { open(dataset("syn", synthetic(9, 200))); }
  static constexpr const char* kPath = "/api/v1/datasets/syn/animation";
  void expect_detail(const Response& r, int status, const std::string& param, const std::string& detail) {
    expect_error(r, status,
                 status == 400   ? "invalid_argument"
                 : status == 404 ? "not_found"
                                 : "payload_too_large",
                 param);
    EXPECT_EQ(body(r)["detail"], detail);
  }
};

TEST_F(AnimationRoute, ServesTheChunkWithETagAndCache) {
  const TrailSet& set = *store->get("syn")->trails;
  const std::string t = std::to_string(static_cast<long long>(kDay + 36000));
  const Response r = get(kPath, {{"t", t}});
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(r.content_type, "application/vnd.trailscope.anim");
  EXPECT_EQ(header(r, "Cache-Control"), "public, max-age=300");
  const std::string etag = header(r, "ETag");
  ASSERT_GE(etag.size(), 3u);
  EXPECT_EQ(etag.front(), '"');  // strong: no W/
  const Decoded d = decode(r.bytes());
  EXPECT_EQ(d.t_start, kDay + 36000);
  EXPECT_EQ(d.duration, 300);
  EXPECT_GT(d.flights.size(), 5u);
  EXPECT_GT(expect_selection(set, kDay + 36000, 300), 50u);
  EXPECT_EQ(r.bytes(), encode_animation_chunk(set, animation_chunk(set, kDay + 36000, 300, Query{}, 1u << 30),
                                              default_animation_origin(set)));
  EXPECT_EQ(app->animation_chunks.entries(), 1u);
  EXPECT_EQ(app->animation_chunks.bytes(), r.bytes().size());
  // Served again from the cache, same ETag; ISO 8601 names the same chunk.
  const Response again = get(kPath, {{"t", "2018-01-01T10:00:00Z"}, {"duration", "300"}});
  EXPECT_EQ(header(again, "ETag"), etag);
  EXPECT_EQ(again.bytes(), r.bytes());
  EXPECT_EQ(app->animation_chunks.entries(), 1u);
  // If-None-Match → 304 without a body.
  const Response not_modified = get(kPath, {{"t", t}}, {{"if-none-match", etag}});
  EXPECT_EQ(not_modified.status, 304);
  EXPECT_TRUE(not_modified.bytes().empty());
  EXPECT_EQ(header(not_modified, "ETag"), etag);
  // Another chunk, duration, origin or filter is another ETag.
  for (const auto& q : std::vector<std::map<std::string, std::string>>{
           {{"t", std::to_string(static_cast<long long>(kDay + 36300))}},
           {{"t", t}, {"duration", "60"}},
           {{"t", t}, {"origin", "10,50"}},
           {{"t", t}, {"callsign", "ABC"}}}) {
    const Response o = get(kPath, q);
    ASSERT_EQ(o.status, 200) << o.body;
    EXPECT_NE(header(o, "ETag"), etag);
  }
  // A given origin is the header's origin.
  const Decoded o = decode(get(kPath, {{"t", t}, {"origin", "10,50"}}).bytes());
  EXPECT_DOUBLE_EQ(o.ox, kR * 10 * kPi / 180);
  EXPECT_DOUBLE_EQ(o.oy, kR * std::asinh(std::tan(50 * kPi / 180)));
  // Deleting the dataset drops its chunks.
  EXPECT_EQ(send("DELETE", "/api/v1/datasets/syn").status, 204);
  EXPECT_EQ(app->animation_chunks.entries(), 0u);
}

TEST_F(AnimationRoute, RefusalsNameTheParameter) {
  const std::string t = std::to_string(static_cast<long long>(kDay + 36000));
  expect_detail(
      get(kPath, {{"t", std::to_string(static_cast<long long>(kDay + 36001))}}), 400, "t",
      "t: chunks start at multiples of duration=300; the nearest starts are 1514800800 and 1514801100");
  expect_detail(
      get(kPath, {{"t", t}, {"duration", "70"}}), 400, "t",
      "t: chunks start at multiples of duration=70; the nearest starts are 1514800770 and 1514800840");
  expect_detail(get(kPath, {{"t", t}, {"duration", "5"}}), 400, "duration",
                "duration must lie in 10..3600, got 5");
  expect_detail(get(kPath, {{"t", t}, {"duration", "7200"}}), 400, "duration",
                "duration must lie in 10..3600, got 7200");
  expect_detail(get(kPath, {}), 400, "t",
                "t: the chunk start is required (?t=Unix seconds or ISO 8601, a multiple of duration)");
  const std::string refused =
      " does not apply to animation chunks: the player filters positions during playback, and the chunk is "
      "the "
      "time window";
  expect_detail(get(kPath, {{"t", t}, {"bbox", "0,40,10,50"}}), 400, "bbox", "bbox" + refused);
  expect_detail(get(kPath, {{"t", t}, {"alt_min", "1000"}}), 400, "alt_min", "alt_min" + refused);
  expect_detail(get(kPath, {{"t", t}, {"alt_max", "1000"}}), 400, "alt_max", "alt_max" + refused);
  expect_detail(get(kPath, {{"t", t}, {"alt_unit", "m"}}), 400, "alt_unit", "alt_unit" + refused);
  expect_detail(get(kPath, {{"t", t}, {"on_ground", "true"}}), 400, "on_ground", "on_ground" + refused);
  expect_detail(get(kPath, {{"t", t}, {"t0", t}}), 400, "t0", "t0" + refused);
  expect_detail(get(kPath, {{"t", t}, {"t1", t}}), 400, "t1", "t1" + refused);
  expect_detail(
      get(kPath, {{"t", t}, {"origin", "10"}}), 400, "origin",
      "origin: expected 'lon,lat' in degrees (lon in [-180, 180], |lat| <= 85.0511287798), got '10'");
  expect_detail(
      get(kPath, {{"t", t}, {"origin", "10,89"}}), 400, "origin",
      "origin: expected 'lon,lat' in degrees (lon in [-180, 180], |lat| <= 85.0511287798), got '10,89'");
  expect_detail(get(kPath, {{"t", t}, {"speed", "1"}}), 400, "speed", "unknown query parameter 'speed'");
  expect_detail(get("/api/v1/datasets/nope/animation", {{"t", t}}), 404, "dataset",
                body(get("/api/v1/datasets/nope"))["detail"]);
  // A refused request never gets a 304, whatever it sends.
  const std::string etag = header(get(kPath, {{"t", t}}), "ETag");
  EXPECT_EQ(get(kPath, {{"t", t}, {"bbox", "0,40,10,50"}}, {{"if-none-match", etag}}).status, 400);
  EXPECT_EQ(app->animation_chunks.entries(), 1u);  // refusals cache nothing
}

TEST_F(AnimationRoute, GarbageParametersNeverGiveServerErrors) {
  const std::vector<std::string> keys = {"t", "duration", "origin", "callsign", "icao24", "bbox", "alt_min"};
  const int n = expect_no_server_errors(
      {kPath}, keys, garbage_values({"1514800800", "300", "10,50", "2018-01-01T10:00:00Z", "60"}), 150, 3, 5);
  EXPECT_EQ(n, 150);
}

// Over kMaxAnimationChunkSamples samples in one chunk: 413 naming duration, and nothing cached.
class AnimationRouteLimits : public test_routes::RouteFixture {};
TEST_F(AnimationRouteLimits, OverTheSampleCapIs413) {
  const std::size_t per = 3600, flights = limits::kMaxAnimationChunkSamples / per + 1;
  PointColumns pts;
  pts.resize(per * flights);
  std::vector<Flight> fl(flights);
  for (std::size_t f = 0; f < flights; ++f) {
    fl[f].begin = static_cast<std::uint32_t>(f * per), fl[f].end = static_cast<std::uint32_t>((f + 1) * per);
    char icao[7];
    std::snprintf(icao, sizeof icao, "%06zx", f + 1);
    fl[f].icao24 = icao;
    for (std::size_t i = 0; i < per; ++i) {
      const std::size_t p = f * per + i;
      pts.t[p] = kDay + static_cast<double>(i), pts.lat[p] = 50, pts.lon[p] = static_cast<float>(i) * 1e-3f;
      pts.alt[p] = pts.speed[p] = pts.track[p] = pts.vrate[p] = 0, pts.on_ground[p] = 0;
    }
    compute_extents(fl[f], pts);
  }
  open(dataset("big", TrailSet(std::move(pts), std::move(fl))));
  const std::string path = "/api/v1/datasets/big/animation", t = std::to_string(static_cast<long long>(kDay));
  const Response res = get(path, {{"t", t}, {"duration", "3600"}});
  EXPECT_EQ(res.status, 413) << res.body;
  const auto j = nlohmann::json::parse(res.body);
  EXPECT_EQ(j["param"], "duration");
  EXPECT_EQ(j["detail"], "the chunk holds " + std::to_string(per * flights) + " samples, more than " +
                             std::to_string(limits::kMaxAnimationChunkSamples) +
                             "; ask for a shorter duration or filter by callsign or icao24");
  EXPECT_EQ(app->animation_chunks.entries(), 0u);
  EXPECT_EQ(get(path, {{"t", t}, {"duration", "60"}}).status, 200);  // a minute of it is fine
}

}  // namespace
}  // namespace trailscope::server
