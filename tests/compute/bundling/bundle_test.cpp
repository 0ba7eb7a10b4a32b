// The public bundling API on the C++ reference (bundle_ref, and bundle with Backend::cpu): determinism,
// styles, relaxation, quality figures, parameters and errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "../../../compute/src/bundling/directional.hpp"
#include "../../../compute/src/bundling/endpoints.hpp"
#include "trailscope/bundling/bundle.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/density/density_lines.hpp"
#include "trailscope/core/limits.hpp"

namespace trailscope::bundling {
namespace {

// A small "airline" graph: hubs and spokes in a 1000 × 700 source box, fitted into `size` px.
Polylines hubs_graph(int edges, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ux(0, 1000), uy(0, 700);
  std::vector<std::pair<double, double>> nodes;
  for (int i = 0; i < 40; ++i) nodes.emplace_back(ux(rng), uy(rng));
  std::uniform_int_distribution<int> pick(0, 39), hub(0, 3);
  Polylines p;
  for (int e = 0; e < edges; ++e) {
    const int a = e % 3 == 0 ? hub(rng) : pick(rng);
    int b = pick(rng);
    if (b == a) b = (b + 1) % 40;
    p.add_edge(nodes[a].first, nodes[a].second, nodes[b].first, nodes[b].second);
  }
  return p;
}

struct Fitted {
  Frame frame;
  Polylines px;
};
Fitted fitted(const Polylines& src, const BundleParams& p) {
  Fitted f;
  f.frame = Frame::fit(src, p.size, p.border, true);
  f.px = f.frame.to_pixels(src);
  return f;
}

BundleParams small_params() {
  BundleParams p;
  p.size = 256;
  p.h = 16;
  p.spl = 8;
  p.iterations = 10;
  return p;
}

void expect_error(const std::function<void()>& f, Error::Kind kind, const std::string& param,
                  const std::string& message) {
  try {
    f();
    ADD_FAILURE() << "no error; expected " << message;
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), kind) << e.what();
    EXPECT_EQ(e.param(), param) << e.what();
    if (!message.empty()) EXPECT_EQ(std::string(e.what()), message);
  }
}

TEST(Bundle, SameSeedSameBytesOtherSeedDifferent) {
  const BundleParams p = small_params();
  const Fitted f = fitted(hubs_graph(150, 1), p);
  const Bundled a = bundle_ref(f.px, f.frame, p), b = bundle_ref(f.px, f.frame, p);
  EXPECT_EQ(a.lines.x, b.lines.x);
  EXPECT_EQ(a.lines.y, b.lines.y);
  EXPECT_EQ(a.lines.offsets, b.lines.offsets);
  EXPECT_EQ(a.path, "cpu");
  BundleParams q = p;
  q.seed = 2;
  const Bundled c = bundle_ref(f.px, f.frame, q);
  EXPECT_NE(a.lines.x, c.lines.x);
  // bundle() on the cpu backend is the reference.
  const Bundled d = bundle(f.px, f.frame, p, Backend::cpu);
  EXPECT_EQ(d.lines.x, a.lines.x);
  EXPECT_EQ(d.path, "cpu");
  EXPECT_EQ(d.device, "");
}

TEST(Bundle, BundlingReducesInkAndReportsEverything) {
  const BundleParams p = small_params();
  const Fitted f = fitted(hubs_graph(300, 4), p);
  int calls = 0;
  double last = 0;
  const Bundled b = bundle_ref(f.px, f.frame, p, [&](double frac, std::string_view stage) {
    ++calls;
    EXPECT_GE(frac, last);
    last = frac;
    EXPECT_TRUE(stage == "bundle" || stage == "post") << stage;
  });
  EXPECT_EQ(calls, p.iterations + 1);
  EXPECT_EQ(b.lines.size(), 300u);
  EXPECT_EQ(b.original.points(), b.lines.points());
  EXPECT_EQ(b.t.size(), b.lines.points());
  EXPECT_EQ(b.displacement.size(), b.lines.points());
  ASSERT_EQ(b.length.size(), 300u);
  EXPECT_GT(b.quality.ink_raw_px, 0u);
  EXPECT_LT(b.quality.ink_bundled_px, b.quality.ink_raw_px);
  EXPECT_GT(b.quality.ink_reduction, 0.1);
  EXPECT_GT(b.quality.mean_displacement_px, 0);
  EXPECT_GE(b.quality.max_displacement_px, b.quality.mean_displacement_px);
  EXPECT_GT(b.times.total_ms, 0);
  EXPECT_GE(b.times.total_ms, b.times.convolve_ms + b.times.advect_ms);
  for (std::size_t e = 0; e < 300; ++e) {
    const std::size_t i = f.px.begin(e), j = f.px.end(e) - 1;
    EXPECT_NEAR(b.length[e], std::hypot(f.px.x[j] - f.px.x[i], f.px.y[j] - f.px.y[i]), 1e-3);
    EXPECT_NEAR(b.angle[e], std::atan2(f.px.y[j] - f.px.y[i], f.px.x[j] - f.px.x[i]), 1e-6);
    EXPECT_EQ(b.t[b.lines.begin(e)], 0.0f);
    EXPECT_EQ(b.t[b.lines.end(e) - 1], 1.0f);
  }
  for (float d : b.displacement) {
    EXPECT_GE(d, 0.0f);
    EXPECT_LE(d, 1.0f);
  }
}

TEST(Bundle, EndpointsNeverMoveWithBlockEndpoints) {
  BundleParams p = small_params();
  const Fitted f = fitted(hubs_graph(200, 5), p);
  const Bundled b = bundle_ref(f.px, f.frame, p);
  for (std::size_t e = 0; e < f.px.size(); ++e) {
    EXPECT_EQ(b.lines.x[b.lines.begin(e)], static_cast<float>(f.px.x[f.px.begin(e)]));
    EXPECT_EQ(b.lines.y[b.lines.begin(e)], static_cast<float>(f.px.y[f.px.begin(e)]));
    EXPECT_EQ(b.lines.x[b.lines.end(e) - 1], static_cast<float>(f.px.x[f.px.end(e) - 1]));
    EXPECT_EQ(b.lines.y[b.lines.end(e) - 1], static_cast<float>(f.px.y[f.px.end(e) - 1]));
  }
  // Without blocking, some endpoint moves.
  p.block_endpoints = false;
  const Bundled m = bundle_ref(f.px, f.frame, p);
  int moved = 0;
  for (std::size_t e = 0; e < f.px.size(); ++e)
    moved += m.lines.x[m.lines.begin(e)] != static_cast<float>(f.px.x[f.px.begin(e)]);
  EXPECT_GT(moved, 10);
}

// Mean distance of the points in the outer 10 % of each edge from their straight original edge.
double end_displacement(const Bundled& b, const Polylines& in) {
  double sum = 0;
  int n = 0;
  for (std::size_t e = 0; e < in.size(); ++e) {
    const double ax = in.x[in.begin(e)], ay = in.y[in.begin(e)];
    const double dx = in.x[in.begin(e) + 1] - ax, dy = in.y[in.begin(e) + 1] - ay;
    const double len = std::hypot(dx, dy);
    if (len < 20) continue;
    for (std::size_t i = b.lines.begin(e); i < b.lines.end(e); ++i)
      if (b.t[i] < 0.1f || b.t[i] > 0.9f) {
        sum += std::fabs((b.lines.x[i] - ax) * dy - (b.lines.y[i] - ay) * dx) / len;
        ++n;
      }
  }
  return sum / n;
}

TEST(Bundle, HourglassKeepsTheEndsNearerTheirEdges) {
  BundleParams p = small_params();
  const Fitted f = fitted(hubs_graph(300, 6), p);
  const Bundled u = bundle_ref(f.px, f.frame, p);
  p.profile = Profile::hourglass;
  const Bundled h = bundle_ref(f.px, f.frame, p);
  EXPECT_LT(end_displacement(h, f.px), 0.75 * end_displacement(u, f.px));
}

TEST(Bundle, RelaxationBlendsTowardTheOriginalWithinTheCap) {
  const BundleParams p = small_params();
  const Fitted f = fitted(hubs_graph(200, 7), p);
  const Bundled b = bundle_ref(f.px, f.frame, p);
  const Polylines one = relax(b, 1, 0.2);
  EXPECT_EQ(one.x, b.original.x);
  EXPECT_EQ(one.y, b.original.y);
  const Polylines zero = relax(b, 0, 10);
  EXPECT_EQ(zero.x, b.lines.x);
  EXPECT_EQ(zero.y, b.lines.y);
  // The cap: no point further than max_displacement · length from its original.
  const Polylines capped = relax(b, 0, 0.05);
  int at_cap = 0;
  for (std::size_t e = 0; e < b.lines.size(); ++e)
    for (std::size_t i = b.lines.begin(e); i < b.lines.end(e); ++i) {
      const double d = std::hypot(capped.x[i] - b.original.x[i], capped.y[i] - b.original.y[i]);
      const double cap = 0.05 * b.length[e];
      EXPECT_LE(d, cap * (1 + 1e-12) + 1e-9);
      at_cap += std::fabs(d - cap) < 1e-6 * cap;
    }
  EXPECT_GT(at_cap, 0);
  // Halfway: the midpoint (where the cap does not bind).
  const Polylines half = relax(b, 0.5, 10);
  for (std::size_t i = 0; i < b.lines.points(); i += 7)
    EXPECT_NEAR(half.x[i], 0.5 * b.lines.x[i] + 0.5 * b.original.x[i], 1e-9);
  expect_error([&] { relax(b, 1.5, 0.2); }, Error::Kind::invalid_argument, "relaxation", "");
  expect_error([&] { relax(b, 0.5, -1); }, Error::Kind::invalid_argument, "max_displacement", "");
}

TEST(Bundle, DirectionSeparationPutsTheTwoDirectionsOnOppositeSides) {
  BundleParams p = small_params();
  Polylines src;
  for (int i = 0; i < 10; ++i) {
    src.add_edge(0, i, 100, i);  // eastbound
    src.add_edge(100, i, 0, i);  // westbound
  }
  const Fitted f = fitted(src, p);
  p.dir_separation = 4;
  const Bundled b = bundle_ref(f.px, f.frame, p);
  p.dir_separation = 0;
  const Bundled n = bundle_ref(f.px, f.frame, p);
  // Middle point of each edge: eastbound ones moved one way, westbound the other, by 4 px.
  for (std::size_t e = 0; e < 20; ++e) {
    const std::size_t mid = (b.lines.begin(e) + b.lines.end(e)) / 2;
    const double dy = b.lines.y[mid] - n.lines.y[mid];
    EXPECT_NEAR(std::fabs(dy), 4 * std::pow(1 - 2 * std::fabs(b.t[mid] - 0.5), 0.4), 0.3) << e;
    EXPECT_EQ(dy < 0, e % 2 == 0) << e;  // tangent × ẑ = (ty, −tx): eastbound moves to −y
  }
}

TEST(Bundle, MeanShiftMergesTheEndpointsOfNearbyNodes) {
  BundleParams p = small_params();
  p.ms_iterations = 10;
  p.ms_h = 16;
  // Two nodes 5 px apart, each with 20 edges to far-away targets on a circle.
  detail::Points pts;
  for (int i = 0; i < 40; ++i) {
    const double a = i * 0.157;
    const float sx = i < 20 ? 100.0f : 105.0f;
    pts.x.push_back(sx), pts.y.push_back(128.0f);
    pts.x.push_back(static_cast<float>(128 + 100 * std::cos(a))),
        pts.y.push_back(static_cast<float>(128 + 100 * std::sin(a)));
    pts.z.insert(pts.z.end(), {1, 1});
    pts.edge.insert(pts.edge.end(), {static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(i)});
    pts.offsets.push_back(static_cast<std::uint32_t>(pts.x.size()));
  }
  const std::vector<std::uint32_t> w(40, 1);
  const detail::Points ends = detail::mean_shift_endpoints(pts, p, w, {}, nullptr);
  const double gap = std::hypot(ends.x[0] - ends.x[2 * 25], ends.y[0] - ends.y[2 * 25]);
  EXPECT_LT(gap, 1.0);  // from 5 px
  // And in the bundle: the clustered ends become the second and second-to-last points before the loop.
  const detail::Points c = detail::cluster_endpoints(pts, p, w, {}, nullptr);
  ASSERT_EQ(c.offsets[1], 4u);
  EXPECT_EQ(c.x[0], 100.0f);
  EXPECT_EQ(c.x[1], ends.x[0]);
  EXPECT_EQ(c.x[2], ends.x[1]);
  EXPECT_EQ(c.x[3], pts.x[1]);
}

// Mean |y| distance between the eastbound and the westbound polylines' middle points.
double lane_gap(const Bundled& b) {
  double east = 0, west = 0;
  for (std::size_t e = 0; e < b.lines.size(); ++e) {
    const std::size_t mid = (b.lines.begin(e) + b.lines.end(e)) / 2;
    (e % 2 == 0 ? east : west) += b.lines.y[mid];
  }
  return std::fabs(east - west) / (b.lines.size() / 2);
}

TEST(Bundle, DirectionalSeparatesAntiparallelEdges) {
  BundleParams p = small_params();
  Polylines src;
  for (int i = 0; i < 12; ++i) {
    src.add_edge(0, 3 * i, 200, 3 * i + 1);          // eastbound
    src.add_edge(200, 3 * i + 1.5, 0, 3 * i + 0.5);  // westbound, interleaved
  }
  const Fitted f = fitted(src, p);
  const Bundled plain = bundle_ref(f.px, f.frame, p);
  p.directional = true;
  const Bundled dir = bundle_ref(f.px, f.frame, p);
  EXPECT_GT(lane_gap(dir), 3 * lane_gap(plain) + 1) << lane_gap(dir) << " vs " << lane_gap(plain);
  // Without repulsion the antiparallel edges do not push apart as much.
  p.repulsion = 0;
  const Bundled weak = bundle_ref(f.px, f.frame, p);
  EXPECT_LT(lane_gap(weak), lane_gap(dir));
}

TEST(Bundle, DirectionHelpers) {
  for (double a = -3.1; a < 3.15; a += 0.1) {
    EXPECT_NEAR(detail::atan2_poly(std::sin(a), std::cos(a)), a, 2e-5) << a;
    EXPECT_NEAR(detail::atan2_poly(5 * std::sin(a), 5 * std::cos(a)), a, 2e-5) << a;
  }
  EXPECT_EQ(detail::atan2_poly(0, 0), 0);
  EXPECT_DOUBLE_EQ(detail::direction_compatibility(0.3, 0.3), 1);
  EXPECT_NEAR(detail::direction_compatibility(0, 3.141592653589793), -1, 1e-15);
  EXPECT_NEAR(detail::direction_compatibility(0, 1.5707963267948966), 0, 1e-15);
  EXPECT_NEAR(detail::direction_compatibility(3.0, -3.0),
              1 - (2 * 3.141592653589793 - 6) * 2 / 3.141592653589793, 1e-12);
}

TEST(Bundle, InkPixelsCountsCoveredPixels) {
  Polylines p;
  p.add_edge(2.5, 3.5, 12.5, 3.5);  // 11 pixels of row 3
  EXPECT_EQ(ink_pixels(p, 32), 11u);
  p.add_edge(2.5, 3.5, 2.5, 10.5);  // 8 more pixels of column 2, one shared
  EXPECT_EQ(ink_pixels(p, 32), 18u);
  Polylines out;
  out.add_edge(-10, -10, -5, 40);
  EXPECT_EQ(ink_pixels(out, 32), 0u);
}

// Many points: ink_pixels rasterises parts of the polylines on several threads and merges their
// coverage; the count must be that of one rasterisation of every segment (density_lines_ref).
TEST(Bundle, InkPixelsOfManyPolylinesIsOneRasterisation) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> start(-3, 259), step(-1.5, 1.5);
  Polylines p;  // short wiggles over (and a little beyond) a 256 px image
  for (int e = 0; e < 20000; ++e) {
    std::vector<double> x{start(rng)}, y{start(rng)};
    for (int i = 1; i < 5; ++i) x.push_back(x.back() + step(rng)), y.push_back(y.back() + step(rng));
    p.add(x, y);
  }
  ASSERT_GT(p.points(), 4u * 16384);  // more than one part (quality.cpp)
  const int size = 256;
  const density::Canvas canvas(0, 0, 256, size, size);
  density::LineSegments s = density::LineSegments::for_canvas(canvas, false);
  auto units = [](double v) { return static_cast<std::int64_t>(std::llround(v * 256)); };
  for (std::size_t e = 0; e < p.size(); ++e)
    for (std::size_t k = p.begin(e); k + 1 < p.end(e); ++k)
      density::append_segment(s, canvas, {units(p.x[k]), units(p.y[k])},
                              {units(p.x[k + 1]), units(p.y[k + 1])}, k > p.begin(e));
  const density::Aggregate a = density::density_lines_ref(s);
  const auto covered = std::count_if(a.count.begin(), a.count.end(), [](std::int32_t c) { return c > 0; });
  EXPECT_EQ(ink_pixels(p, size), static_cast<std::uint64_t>(covered));
  EXPECT_LT(covered, size * size);  // not trivially full
}

TEST(Bundle, ErrorsNameTheirCause) {
  const BundleParams p = small_params();
  const Fitted f = fitted(hubs_graph(20, 8), p);
  BundleParams bad = p;
  bad.h = 1;
  expect_error([&] { bundle_ref(f.px, f.frame, bad); }, Error::Kind::invalid_argument, "h",
               "h must be in [2, 128] px (got 1)");
  bad = p;
  bad.smooth_iterations = 2;
  expect_error([&] { bundle_ref(f.px, f.frame, bad); }, Error::Kind::invalid_argument, "smooth_iterations",
               "smooth_iterations must be an odd integer in 1..15 (got 2)");
  bad = p;
  bad.eps = 0;
  expect_error([&] { bundle(f.px, f.frame, bad, Backend::cpu); }, Error::Kind::invalid_argument, "eps",
               "eps must be in (0, 2] (got 0)");
  expect_error([&] { bundle_ref(Polylines{}, f.frame, p); }, Error::Kind::unprocessable, "input",
               "nothing to bundle: the input has no polylines");
  Polylines one_point;
  one_point.add(std::vector<double>{1.0}, std::vector<double>{2.0});
  expect_error([&] { bundle_ref(one_point, f.frame, p); }, Error::Kind::unprocessable, "input",
               "polyline 0 has 1 point(s); at least 2 are needed");
  Polylines nan_point;
  nan_point.add_edge(0, 0, NAN, 3);
  expect_error([&] { bundle_ref(nan_point, f.frame, p); }, Error::Kind::unprocessable, "input",
               "point 1 is not finite");
  Frame other = f.frame;
  other.size = 512;
  expect_error([&] { bundle_ref(f.px, other, p); }, Error::Kind::invalid_argument, "size",
               "the frame is for 512 px but size is 256");
  Polylines huge;
  huge.add_edge(0, 0, 1e9, 0);
  BundleParams fine = p;
  fine.spl = 1;
  expect_error([&] { bundle_ref(huge, f.frame, fine); }, Error::Kind::payload_too_large, "input",
               "resampling makes more than " + std::to_string(limits::kMaxBundlePoints) +
                   " points (limits::kMaxBundlePoints); use a larger spl or fewer polylines");
}

TEST(Bundle, CancellationStopsBetweenIterations) {
  const BundleParams p = small_params();
  const Fitted f = fitted(hubs_graph(50, 9), p);
  CancelToken token;
  int iterations = 0;
  auto progress = [&](double, std::string_view stage) {
    if (stage == "bundle" && ++iterations == 3) token.cancel();
  };
  expect_error([&] { bundle_ref(f.px, f.frame, p, progress, &token); }, Error::Kind::cancelled, "",
               "operation cancelled");
  EXPECT_EQ(iterations, 3);
}

TEST(BundleParamsTest, SetValidateAndMap) {
  BundleParams p;
  p.set("h", "24");
  p.set("profile", "hourglass");
  p.set("block_endpoints", "false");
  p.set("seed", "18446744073709551615");
  EXPECT_EQ(p.h, 24);
  EXPECT_EQ(p.profile, Profile::hourglass);
  EXPECT_FALSE(p.block_endpoints);
  EXPECT_EQ(p.seed, 18446744073709551615ull);
  const auto m = p.to_map();
  EXPECT_EQ(m.at("h"), "24");
  EXPECT_EQ(m.at("smooth_kernel"), "0.05");
  EXPECT_EQ(m.at("profile"), "hourglass");
  EXPECT_EQ(m.size(), parameter_infos().size());
  // Every parameter reads back from its own text.
  BundleParams q;
  for (const auto& [name, value] : m) q.set(name, value);
  EXPECT_EQ(q.to_map(), m);
  for (const ParamInfo& info : parameter_infos()) {
    EXPECT_FALSE(info.help.empty()) << info.name;
    EXPECT_EQ(BundleParams{}.to_map().at(info.name), info.default_value) << info.name;
  }
  expect_error([&] { p.set("nope", "1"); }, Error::Kind::invalid_argument, "nope",
               "unknown bundling parameter 'nope'");
  expect_error([&] { p.set("size", "abc"); }, Error::Kind::invalid_argument, "size",
               "size must be an integer (got 'abc')");
  expect_error([&] { p.set("size", "99999999999"); }, Error::Kind::invalid_argument, "size",
               "size must be an integer in 64..4096 px (got 99999999999)");
  expect_error([&] { p.set("lambda", "1.5"); }, Error::Kind::invalid_argument, "lambda",
               "lambda must be in [0, 1] (got 1.5)");
  expect_error([&] { p.set("density", "fast"); }, Error::Kind::invalid_argument, "density",
               "density must be weighted or count (got 'fast')");
  EXPECT_EQ(p.h, 24);  // a failed set changes nothing
  BundleParams{}.validate();
  EXPECT_STREQ(to_string(DensityMode::count), "count");
  EXPECT_STREQ(to_string(Profile::uniform), "uniform");
}

TEST(FrameTest, FitCentresAndRoundTrips) {
  Polylines src;
  src.add_edge(10, 20, 110, 70);  // 100 × 50
  const Frame f = Frame::fit(src, 512, 0.1);
  EXPECT_DOUBLE_EQ(f.to_px_x(10), 0.1 * 512);
  EXPECT_DOUBLE_EQ(f.to_px_x(110), 0.9 * 512);
  EXPECT_DOUBLE_EQ(f.to_px_y(20) + f.to_px_y(70), 512);  // centred vertically
  const Frame g = Frame::fit(src, 512, 0.1, true);
  EXPECT_GT(g.to_px_y(20), g.to_px_y(70));  // y up in the source, down in pixels
  const Polylines back = g.from_pixels(g.to_pixels(src));
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_NEAR(back.x[i], src.x[i], 1e-9);
    EXPECT_NEAR(back.y[i], src.y[i], 1e-9);
  }
  const Frame v = Frame::view(0, 0, 200, 100, 400);
  EXPECT_DOUBLE_EQ(v.to_px_x(200), 400);
  EXPECT_DOUBLE_EQ(v.to_px_y(50), 200);
  expect_error([&] { Frame::fit(Polylines{}, 512, 0.1); }, Error::Kind::unprocessable, "input", "");
  Polylines dot;
  dot.add_edge(1, 1, 1, 1);
  expect_error([&] { Frame::fit(dot, 512, 0.1); }, Error::Kind::unprocessable, "input", "");
  expect_error([&] { Frame::view(0, 0, 0, 1, 512); }, Error::Kind::invalid_argument, "bbox", "");
}

}  // namespace
}  // namespace trailscope::bundling
