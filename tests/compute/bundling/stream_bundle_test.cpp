// Streaming CUBu bundling (trailscope/bundling/streaming.hpp): which trails a window holds and their
// fades against a brute-force reading of the definition, the drift per update recomputed from the
// outputs, the converged stream against a from-scratch bundling of the same window, OpenCL against the
// reference on every update (strict mode, same bits), and the errors.
//
// QUALITY MEASURE (what "matches a from-scratch bundle" means): run the stream over a moving clock,
// then hold the clock and keep updating until the mean drift falls below 0.05 px per update; bundle the
// same window from scratch (a fresh bundler at that instant: every trail unbundled, updated as many
// times as the stream's hold plus kFromScratchUpdates). Two distances, pixels of the 512-px frame:
//  - shape: per point of each streamed trail, its distance to the same trail's from-scratch polyline
//    (closest point of its segments): how differently the two DRAW the trail. Tolerance: mean <=
//    kShapeMeanTolPx, 95th percentile <= kShapeP95TolPx;
//  - point: per point, its distance to the same point (same index) of the from-scratch trail, which
//    also counts points that slid along their bundle. Tolerance: mean <= kPointMeanTolPx.
// And the bundling is real: the points moved, on average, more than kMovedOverShape times the shape
// mean from their unbundled positions.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <string>

#include "strict_opencl.hpp"
#include "trailscope/bundling/streaming.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/ocl_info.hpp"

namespace trailscope::bundling {
namespace {

constexpr double kShapeMeanTolPx = 1.5;
constexpr double kShapeP95TolPx = 6.0;
constexpr double kPointMeanTolPx = 2.5;
constexpr double kMovedOverShape = 4.0;
constexpr int kFromScratchUpdates = 100;

// Trails between a dozen "airports" of a 512 px plane (source units = pixels), each a noisy straight
// path of 12 points, starting uniformly over 6 h and lasting 20–120 min: structure to bundle, with
// trails entering and leaving all the time.
struct Synthetic {
  std::vector<std::vector<double>> x, y;
  StreamSource source;
};

Synthetic synthetic(std::size_t trails, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(60, 452), start(0, 6 * 3600.0), dur(1200, 7200);
  std::normal_distribution<double> noise(0, 5);
  std::vector<std::pair<double, double>> hubs;
  for (int i = 0; i < 12; ++i) hubs.emplace_back(pos(rng), pos(rng));
  std::uniform_int_distribution<int> pick(0, 11);
  Synthetic s;
  for (std::size_t i = 0; i < trails; ++i) {
    int a = pick(rng), b = pick(rng);
    while (b == a) b = pick(rng);
    std::vector<double> xs, ys;
    const double ax = hubs[a].first + noise(rng), ay = hubs[a].second + noise(rng);
    const double bx = hubs[b].first + noise(rng), by = hubs[b].second + noise(rng);
    for (int k = 0; k < 12; ++k) {
      const double f = k / 11.0;
      xs.push_back(ax + f * (bx - ax) + (k > 0 && k < 11 ? noise(rng) * 0.4 : 0));
      ys.push_back(ay + f * (by - ay) + (k > 0 && k < 11 ? noise(rng) * 0.4 : 0));
    }
    s.x.push_back(xs), s.y.push_back(ys);
    const double t0 = start(rng);
    s.source.trails.push_back({1000 + i, t0, t0 + dur(rng)});
  }
  s.source.geometry = [&s](std::size_t i, std::vector<double>& x, std::vector<double>& y) {
    x = s.x[i], y = s.y[i];
  };
  return s;
}

Frame plane() {
  return Frame::view(0, 0, 512, 512, 512);
}

// The present set by the definition, brute force.
std::set<std::uint64_t> present_at(const StreamSource& src, double t, double W) {
  std::set<std::uint64_t> ids;
  for (const StreamTrail& s : src.trails)
    if (s.t0 <= t && t <= s.t1 + W) ids.insert(s.id);
  return ids;
}

// Per id, the points of one update (pixels).
std::map<std::uint64_t, std::vector<std::pair<double, double>>> by_id(const StreamUpdate& u) {
  std::map<std::uint64_t, std::vector<std::pair<double, double>>> m;
  for (std::size_t e = 0; e < u.id.size(); ++e)
    for (std::size_t k = u.lines.begin(e); k < u.lines.end(e); ++k)
      m[u.id[e]].push_back({u.lines.x[k], u.lines.y[k]});
  return m;
}

TEST(StreamBundle, WindowMembershipAndFadeFollowTheDefinition) {
  Synthetic s = synthetic(600, 3);
  StreamParams p;
  p.window_s = 1800, p.fade_s = 240;
  StreamingBundler b(plane(), p, Backend::cpu);
  std::set<std::uint64_t> prev;
  for (double t = 3600; t <= 3 * 3600; t += 300) {
    const StreamUpdate u = b.update(t, s.source);
    const std::set<std::uint64_t> want = present_at(s.source, t, p.window_s);
    const std::set<std::uint64_t> got(u.id.begin(), u.id.end());
    ASSERT_EQ(got, want) << "t = " << t;
    std::size_t added = 0, removed = 0;
    for (auto id : want) added += !prev.count(id);
    for (auto id : prev) removed += !want.count(id);
    EXPECT_EQ(u.added, added);
    EXPECT_EQ(u.removed, removed);
    EXPECT_EQ(u.persistent, want.size() - added);
    // Opacity: the fade ramp written out piecewise.
    for (std::size_t e = 0; e < u.id.size(); ++e) {
      const StreamTrail& tr = s.source.trails[u.id[e] - 1000];
      double o = 1;
      if (t - tr.t0 < p.fade_s) o = (t - tr.t0) / p.fade_s;
      if (tr.t1 + p.window_s - t < p.fade_s) o = std::min(o, (tr.t1 + p.window_s - t) / p.fade_s);
      EXPECT_NEAR(u.opacity[e], o, 1e-6) << "trail " << u.id[e] << " at t = " << t;
    }
    prev = want;
  }
}

TEST(StreamBundle, EnteringTrailsStartUnbundledOnTheirResampledPath) {
  Synthetic s = synthetic(200, 5);
  StreamParams p;
  p.iterations = 1;
  StreamingBundler b(plane(), p, Backend::cpu);
  const StreamUpdate u = b.update(4 * 3600, s.source);
  ASSERT_GT(u.added, 50u);
  // After one iteration every point is within one step (eps·h) plus the smoothing's pull of its
  // polyline, and the ends (block_endpoints) are exactly the input's ends.
  for (std::size_t e = 0; e < u.id.size(); ++e) {
    const auto& xs = s.x[u.id[e] - 1000];
    const auto& ys = s.y[u.id[e] - 1000];
    EXPECT_FLOAT_EQ(u.lines.x[u.lines.begin(e)], static_cast<float>(xs.front()));
    EXPECT_FLOAT_EQ(u.lines.y[u.lines.end(e) - 1], static_cast<float>(ys.back()));
    // Resampled at spl = 15 px: 2 + interior samples of the input's length.
    double len = 0;
    for (std::size_t k = 1; k < xs.size(); ++k) len += std::hypot(xs[k] - xs[k - 1], ys[k] - ys[k - 1]);
    const std::size_t want = 2 + static_cast<std::size_t>(std::ceil(len / p.spl) - 1);
    EXPECT_NEAR(static_cast<double>(u.lines.end(e) - u.lines.begin(e)), static_cast<double>(want), 1.0);
  }
}

TEST(StreamBundle, ANewSourceWithTheSameIdsKeepsTheTrails) {
  Synthetic s = synthetic(400, 29);
  StreamParams p;
  StreamingBundler b(plane(), p, Backend::cpu);
  const StreamUpdate first = b.update(3 * 3600, s.source);
  // The same trails in reverse order (other indices), half of them only: held trails are found by id.
  StreamSource reversed;
  std::vector<std::size_t> back;
  for (std::size_t i = s.source.trails.size(); i-- > 0;)
    if (i % 2 == 0) reversed.trails.push_back(s.source.trails[i]), back.push_back(i);
  reversed.geometry = [&](std::size_t i, std::vector<double>& x, std::vector<double>& y) {
    s.source.geometry(back[i], x, y);
  };
  const StreamUpdate u = b.update(3 * 3600 + 30, reversed);
  std::size_t kept = 0;
  for (std::uint64_t id : first.id) kept += (id - 1000) % 2 == 0;
  EXPECT_EQ(u.added, present_at(reversed, 3 * 3600 + 30, p.window_s).size() - kept);
  EXPECT_EQ(u.persistent, kept);
  EXPECT_EQ(u.removed, first.id.size() - kept);
  EXPECT_LT(u.drift_px, 2.0);
}

TEST(StreamBundle, DriftPerUpdateIsSmallAndReportedExactly) {
  Synthetic s = synthetic(1500, 7);
  StreamParams p;  // defaults: h = 16, eps = 0.05, 2 iterations
  StreamingBundler b(plane(), p, Backend::cpu);
  StreamUpdate prev = b.update(2 * 3600, s.source);
  double sum = 0;
  int n = 0;
  for (double t = 2 * 3600 + 30; t <= 4 * 3600; t += 30) {
    const StreamUpdate u = b.update(t, s.source);
    // The drift recomputed from the two outputs: points of trails in both, by id.
    const auto a = by_id(prev), c = by_id(u);
    double d = 0, mx = 0;
    std::size_t pts = 0;
    for (const auto& [id, q] : c) {
      const auto it = a.find(id);
      if (it == a.end()) continue;
      ASSERT_EQ(it->second.size(), q.size()) << "a persistent trail keeps its points";
      for (std::size_t k = 0; k < q.size(); ++k) {
        const double dd = std::hypot(q[k].first - it->second[k].first, q[k].second - it->second[k].second);
        d += dd, mx = std::max(mx, dd), ++pts;
      }
    }
    ASSERT_GT(pts, 0u);
    EXPECT_NEAR(u.drift_px, d / pts, 1e-9);
    EXPECT_NEAR(u.max_drift_px, mx, 1e-9);
    // The done-when bound of 2 px mean drift per update, on every update, not only on average.
    EXPECT_LE(u.drift_px, 2.0) << "t = " << t;
    sum += u.drift_px, ++n;
    prev = u;
  }
  EXPECT_LE(sum / n, 2.0);
  EXPECT_GT(sum / n, 0.01) << "the bundles do move";
}

TEST(StreamBundle, ConvergedStreamMatchesAFromScratchBundleOfTheWindow) {
  Synthetic s = synthetic(1500, 11);
  StreamParams p;
  StreamingBundler b(plane(), p, Backend::cpu);
  double t = 2 * 3600;
  for (; t <= 4 * 3600; t += 30) b.update(t, s.source);
  t -= 30;
  // Hold the clock until the stream settles.
  StreamUpdate held;
  int hold = 0;
  do {
    held = b.update(t, s.source);
    ++hold;
  } while (held.drift_px > 0.05 && hold < 400);
  ASSERT_LT(hold, 400) << "the stream does not settle";
  StreamingBundler fresh(plane(), p, Backend::cpu);
  StreamUpdate scratch;
  for (int i = 0; i < hold + kFromScratchUpdates; ++i) scratch = fresh.update(t, s.source);
  const auto a = by_id(held), c = by_id(scratch);
  ASSERT_EQ(a.size(), c.size());
  std::vector<double> point, shape;
  for (const auto& [id, q] : a) {
    const auto& r = c.at(id);
    ASSERT_EQ(q.size(), r.size());
    for (std::size_t k = 0; k < q.size(); ++k) {
      point.push_back(std::hypot(q[k].first - r[k].first, q[k].second - r[k].second));
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t j = 0; j + 1 < r.size(); ++j) {
        const double ax = r[j].first, ay = r[j].second, bx = r[j + 1].first - ax, by = r[j + 1].second - ay;
        const double len2 = bx * bx + by * by;
        const double u =
            len2 > 0 ? std::clamp(((q[k].first - ax) * bx + (q[k].second - ay) * by) / len2, 0.0, 1.0) : 0;
        best = std::min(best, std::hypot(q[k].first - ax - u * bx, q[k].second - ay - u * by));
      }
      shape.push_back(best);
    }
  }
  const auto mean_of = [](const std::vector<double>& v) {
    double m = 0;
    for (double d : v) m += d;
    return m / static_cast<double>(v.size());
  };
  std::sort(shape.begin(), shape.end());
  const double shape_mean = mean_of(shape), shape_p95 = shape[shape.size() * 95 / 100];
  const double point_mean = mean_of(point);
  // ...and bundling did happen: the settled points are far from their unbundled positions.
  StreamParams still = p;
  still.iterations = 1, still.eps = 1e-9, still.anchor = 0;
  StreamingBundler raw(plane(), still, Backend::cpu);
  const auto u0 = by_id(raw.update(t, s.source));
  double moved = 0;
  std::size_t n = 0;
  for (const auto& [id, q] : a)
    for (std::size_t k = 0; k < q.size(); ++k, ++n)
      moved += std::hypot(q[k].first - u0.at(id)[k].first, q[k].second - u0.at(id)[k].second);
  moved /= static_cast<double>(n);
  std::printf(
      "converged stream vs from scratch over %zu points (hold %d): shape mean %.3f px, p95 %.3f px; "
      "point mean %.3f px; bundling moved %.3f px\n",
      shape.size(), hold, shape_mean, shape_p95, point_mean, moved);
  EXPECT_LE(shape_mean, kShapeMeanTolPx);
  EXPECT_LE(shape_p95, kShapeP95TolPx);
  EXPECT_LE(point_mean, kPointMeanTolPx);
  EXPECT_GT(moved, kMovedOverShape * shape_mean);
}

TEST(StreamBundle, FrameChangeCarriesThePointsOver) {
  Synthetic s = synthetic(300, 13);
  StreamParams p;
  StreamingBundler b(plane(), p, Backend::cpu);
  for (int i = 0; i < 10; ++i) b.update(3 * 3600, s.source);
  const StreamUpdate before = b.update(3 * 3600, s.source);
  const Frame zoomed = Frame::view(100, 50, 356, 306, 512);  // 2x, shifted
  b.set_frame(zoomed);
  const StreamUpdate after = b.update(3 * 3600, s.source);
  EXPECT_EQ(after.drift_px, 0.0) << "no drift is reported across a frame change";
  EXPECT_EQ(after.persistent, before.id.size());
  // Points before, mapped by hand (2x, origin (100, 50)), against points after: within the motion of
  // one update (2 iterations of at most eps·h = 1.6 px, smoothing and the anchor's pull of a fifth of
  // at most ~13 px, all times the zoom), where a wrong mapping would be off by tens of pixels.
  const auto a = by_id(before), c = by_id(after);
  double worst = 0;
  for (const auto& [id, pts] : a)
    for (std::size_t k = 0; k < pts.size(); ++k) {
      const double ex = (pts[k].first - 100) * 2, ey = (pts[k].second - 50) * 2;
      worst = std::max(worst, std::hypot(c.at(id)[k].first - ex, c.at(id)[k].second - ey));
    }
  EXPECT_LT(worst, 2 * (2 * 1.6 + 0.2 * 13 + 2));
}

TEST(StreamBundle, Errors) {
  Synthetic s = synthetic(50, 17);
  StreamParams p;
  StreamingBundler b(plane(), p, Backend::cpu);
  try {
    b.update(std::nan(""), s.source);
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::invalid_argument);
    EXPECT_EQ(e.param(), "t");
  }
  // Too many trails: counted before any geometry is read.
  StreamSource many;
  for (std::size_t i = 0; i <= limits::kMaxStreamTrails; ++i) many.trails.push_back({i, 0, 10});
  many.geometry = [](std::size_t, std::vector<double>&, std::vector<double>&) { FAIL() << "geometry read"; };
  try {
    b.update(5, many);
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::payload_too_large);
    EXPECT_EQ(e.param(), "window");
    EXPECT_NE(std::string(e.what()).find("kMaxStreamTrails"), std::string::npos);
  }
  // A one-point trail.
  StreamSource bad;
  bad.trails.push_back({1, 0, 10});
  bad.geometry = [](std::size_t, std::vector<double>& x, std::vector<double>& y) { x = {1}, y = {1}; };
  try {
    b.update(5, bad);
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::unprocessable);
    EXPECT_EQ(e.param(), "geometry");
  }
  EXPECT_EQ(b.trails(), 0u) << "a failed update leaves the state as it was";
  for (auto [name, bad_params] :
       std::vector<std::pair<std::string, StreamParams>>{{"h",
                                                          [] {
                                                            StreamParams q;
                                                            q.h = 1;
                                                            return q;
                                                          }()},
                                                         {"iterations",
                                                          [] {
                                                            StreamParams q;
                                                            q.iterations = limits::kMaxStreamIterations + 1;
                                                            return q;
                                                          }()},
                                                         {"window_s",
                                                          [] {
                                                            StreamParams q;
                                                            q.window_s = limits::kMaxStreamWindowSeconds + 1;
                                                            return q;
                                                          }()},
                                                         {"fade_s",
                                                          [] {
                                                            StreamParams q;
                                                            q.fade_s = q.window_s + 1;
                                                            return q;
                                                          }()},
                                                         {"smooth_iterations", [] {
                                                            StreamParams q;
                                                            q.smooth_iterations = 2;
                                                            return q;
                                                          }()}}) {
    try {
      StreamingBundler x(plane(), bad_params);
      ADD_FAILURE() << name;
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), Error::Kind::invalid_argument);
      EXPECT_EQ(e.param(), name);
    }
  }
  StreamParams q;
  q.size = 256;
  EXPECT_THROW(StreamingBundler(plane(), q), Error);
}

class StreamBundleOcl : public test::StrictOpenCl {};

TEST_F(StreamBundleOcl, EveryUpdateMatchesTheReferenceBitForBit) {
  Synthetic s = synthetic(1200, 19);
  StreamParams p;
  p.iterations = 3, p.smooth_iterations = 3, p.h = 24;
  StreamingBundler ref(plane(), p, Backend::cpu), dev(plane(), p, Backend::opencl);
  int updates = 0;
  for (double t = 2 * 3600; t <= 3 * 3600; t += 120, ++updates) {
    const StreamUpdate a = ref.update(t, s.source), b = dev.update(t, s.source);
    ASSERT_EQ(a.path, "cpu");
    ASSERT_EQ(b.path, "opencl");
    ASSERT_EQ(a.id, b.id);
    ASSERT_EQ(a.lines.offsets, b.lines.offsets);
    ASSERT_EQ(a.lines.x, b.lines.x) << "t = " << t;
    ASSERT_EQ(a.lines.y, b.lines.y) << "t = " << t;
    EXPECT_EQ(a.drift_px, b.drift_px);
  }
  EXPECT_GT(updates, 20);
}

TEST_F(StreamBundleOcl, AFailingDeviceFallsBackToTheReferenceOrThrowsInStrictMode) {
  Synthetic s = synthetic(300, 23);
  StreamParams p;
  const test::ScopedEnv inject("TRAILSCOPE_OPENCL_INJECT_FAILURE", "bundle_stream");
  StreamingBundler dev(plane(), p, Backend::opencl);
  try {
    dev.update(3 * 3600, s.source);
    ADD_FAILURE() << "strict mode let a fallback through";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::backend) << e.what();
  }
  const test::ScopedEnv lenient("TRAILSCOPE_OPENCL_STRICT", "0");
  StreamingBundler dev2(plane(), p, Backend::opencl), ref(plane(), p, Backend::cpu);
  const StreamUpdate b = dev2.update(3 * 3600, s.source);
  EXPECT_EQ(b.path, "cpu");
  EXPECT_EQ(b.lines.x, ref.update(3 * 3600, s.source).lines.x);
}

}  // namespace
}  // namespace trailscope::bundling
