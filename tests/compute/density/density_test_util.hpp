#pragma once
// Helpers shared by the density and ocl tests: an independent, brute-force definition of which pixels a
// segment touches, random segment sets, small synthetic TrailSets and the Europe SO6 day.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "test_support.hpp"
#include "trailscope/density/density.hpp"
#include "trailscope/ingest/ingest.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::test {

using density::Canvas;
using density::MercPoint;

/// Does the closed segment a→b meet the half-open box [x0, x1) × [y0, y1)? Exact (int128 rationals), and
/// written from the definition, independently of the walk: each axis restricts t ∈ [0, 1] to an interval
/// whose ends are open or closed depending on the direction; the segment meets the box iff the
/// intersection of the intervals is not empty.
inline bool segment_meets_box(MercPoint a, MercPoint b, std::int64_t x0, std::int64_t y0, std::int64_t x1,
                              std::int64_t y1) {
  using i128 = __int128;
  struct End {
    i128 num, den;  // t = num/den, den > 0
    bool closed;
  };
  End lo{0, 1, true}, hi{1, 1, true};
  auto later = [](const End& p, const End& q) { return p.num * q.den > q.num * p.den; };
  auto same = [](const End& p, const End& q) { return p.num * q.den == q.num * p.den; };
  auto raise = [&](End e) {  // lo = max(lo, e); at equal t an open end wins
    if (later(e, lo) || (same(e, lo) && !e.closed)) lo = e;
  };
  auto lower = [&](End e) {
    if (later(hi, e) || (same(e, hi) && !e.closed)) hi = e;
  };
  auto axis = [&](std::int64_t p, std::int64_t q, std::int64_t c0, std::int64_t c1) {
    const i128 d = i128{q} - p;
    if (d == 0) return c0 <= p && p < c1;
    if (d > 0) {
      raise(End{i128{c0} - p, d, true});   // p + t·d >= c0
      lower(End{i128{c1} - p, d, false});  // p + t·d < c1
    } else {
      lower(End{i128{p} - c0, -d, true});   // p + t·d >= c0  ⇔  t <= (p − c0)/|d|
      raise(End{i128{p} - c1, -d, false});  // p + t·d < c1   ⇔  t > (p − c1)/|d|
    }
    return true;
  };
  if (!axis(a.x, b.x, x0, x1) || !axis(a.y, b.y, y0, y1)) return false;
  if (later(lo, hi)) return false;
  if (same(lo, hi)) return lo.closed && hi.closed;
  return true;
}

struct Seg {
  MercPoint a, b;
};

/// Counts per pixel of `canvas` by the definition: every copy (shifted by whole worlds) of every segment,
/// drawn the short way round, adds 1 to every pixel whose square it meets. No shared-endpoint rule.
inline std::vector<std::int32_t> brute_counts(const std::vector<Seg>& segs, const Canvas& c) {
  constexpr std::int64_t world = std::int64_t{1} << 32;
  std::vector<std::int32_t> out(static_cast<std::size_t>(c.width()) * c.height(), 0);
  for (Seg s : segs) {
    if (s.b.x - s.a.x > world / 2) s.b.x -= world;
    if (s.b.x - s.a.x < -world / 2) s.b.x += world;
    for (int k = -3; k <= 3; ++k) {
      const MercPoint a{s.a.x + k * world, s.a.y}, b{s.b.x + k * world, s.b.y};
      for (int j = 0; j < c.height(); ++j)
        for (int i = 0; i < c.width(); ++i) {
          const std::int64_t x0 = c.origin_x() + i * c.pixel_units(), y0 = c.origin_y() + j * c.pixel_units();
          if (segment_meets_box(a, b, x0, y0, x0 + c.pixel_units(), y0 + c.pixel_units()))
            ++out[static_cast<std::size_t>(j) * c.width() + i];
        }
    }
  }
  return out;
}

/// Prepared segments of `segs`, none continuing a run.
inline density::LineSegments prepare(const std::vector<Seg>& segs, const Canvas& c, bool with_value = false,
                                     std::mt19937* values = nullptr) {
  density::LineSegments out = density::LineSegments::for_canvas(c, with_value);
  std::uniform_real_distribution<double> v(-500.0, 14000.0);
  for (const Seg& s : segs) density::append_segment(out, c, s.a, s.b, false, values ? v(*values) : NAN);
  return out;
}

/// Random segments around a canvas: endpoints anywhere within `reach` pixels of it, a third of them
/// snapped to pixel corners or edges (so that ties and corner passes are common), some zero-length,
/// axis-parallel or along pixel edges.
inline std::vector<Seg> random_segments(std::mt19937& rng, const Canvas& c, int n, double reach = 0.5) {
  const std::int64_t p = c.pixel_units();
  const std::int64_t w = c.width() * p, h = c.height() * p;
  std::uniform_int_distribution<std::int64_t> ux(-static_cast<std::int64_t>(reach * w),
                                                 w + static_cast<std::int64_t>(reach * w));
  std::uniform_int_distribution<std::int64_t> uy(-static_cast<std::int64_t>(reach * h),
                                                 h + static_cast<std::int64_t>(reach * h));
  std::uniform_int_distribution<int> kind(0, 9);
  auto snap = [&](std::int64_t v) { return v - ((v % p) + p) % p; };
  std::vector<Seg> out;
  for (int k = 0; k < n; ++k) {
    MercPoint a{ux(rng), uy(rng)}, b{ux(rng), uy(rng)};
    switch (kind(rng)) {
      case 0:
        a = {snap(a.x), snap(a.y)}, b = {snap(b.x), snap(b.y)};
        break;  // corner to corner
      case 1:
        b = {a.x + (b.y - a.y), b.y};
        break;  // 45°
      case 2:
        a = {snap(a.x), snap(a.y)}, b = {a.x + (b.y - a.y), b.y};
        break;  // 45° through corners
      case 3:
        b.y = a.y;
        break;  // horizontal
      case 4:
        b.x = a.x = snap(a.x);
        break;  // vertical on an edge
      case 5:
        b = a;
        break;  // zero length
      case 6:
        a.y = b.y = snap(a.y);
        break;  // along a pixel edge
      default:
        break;
    }
    out.push_back(Seg{{a.x + c.origin_x(), a.y + c.origin_y()}, {b.x + c.origin_x(), b.y + c.origin_y()}});
  }
  return out;
}

/// A TrailSet from polylines of (lon, lat) with one sample a minute, altitude rising 100 m per sample.
inline TrailSet polylines(const std::vector<std::vector<std::pair<double, double>>>& lines) {
  TrailSetBuilder b;
  int id = 0;
  for (const auto& line : lines) {
    char icao[8];
    std::snprintf(icao, sizeof icao, "%06x", 0xa00000 + id);
    double t = 1514764800.0 + 3600.0 * id;
    float alt = 1000.0f;
    for (const auto& [lon, lat] : line) {
      Sample s;
      s.t = t;
      s.lon = static_cast<float>(lon);
      s.lat = static_cast<float>(lat);
      s.alt = alt;
      s.speed = 200.0f;
      b.add(icao, "TEST" + std::to_string(id), s);
      t += 60.0;
      alt += 100.0f;
    }
    ++id;
  }
  return b.build();
}

/// A small synthetic set over western Europe: a fan of 24 routes from Paris, a ring around the Alps, 40
/// nearly parallel lines across France and Germany, and a zig-zag over Spain.
inline const TrailSet& synthetic() {
  static const TrailSet set = [] {
    std::vector<std::vector<std::pair<double, double>>> lines;
    for (int k = 0; k < 24; ++k) {
      const double a = k * M_PI / 12;
      lines.push_back({{2.35, 48.85},
                       {2.35 + 4 * std::cos(a), 48.85 + 3 * std::sin(a)},
                       {2.35 + 11 * std::cos(a), 48.85 + 8 * std::sin(a)}});
    }
    std::vector<std::pair<double, double>> ring;
    for (int k = 0; k <= 72; ++k)
      ring.push_back({10 + 6 * std::cos(k * M_PI / 36), 45 + 4 * std::sin(k * M_PI / 36)});
    lines.push_back(ring);
    for (int k = 0; k < 40; ++k) lines.push_back({{-5.0, 44.0 + k * 0.2}, {15.0, 46.0 + k * 0.25}});
    std::vector<std::pair<double, double>> zig;
    for (int k = 0; k < 30; ++k) zig.push_back({-8 + k * 0.8, 40 + (k % 2) * 3.0});
    lines.push_back(zig);
    return polylines(lines);
  }();
  return set;
}

/// The Europe SO6 day (11,043 flights), loaded once; nullptr when the shared data is absent.
inline const TrailSet* europe() {
  static const std::unique_ptr<TrailSet> set = []() -> std::unique_ptr<TrailSet> {
    const auto path = shared_data("flights/traffic_europe_20180101_m3.so6.gz");
    if (!std::filesystem::exists(path)) return nullptr;
    return std::make_unique<TrailSet>(ingest::ingest_file(path.string()));
  }();
  return set.get();
}

}  // namespace trailscope::test
