// render_bundle on hand-made bundles: each expectation is computed here from the formulas of render.hpp
// (cushion, rainbow, HSV, colour maps, "over" compositing), on lines laid along pixel centres with a
// vertex per pixel so that a pixel's colour is exactly its vertex's.
#include <gtest/gtest.h>

#include <cmath>

#include "render_test_util.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/density/colormap.hpp"
#include "trailscope/density/png.hpp"

namespace trailscope::bundling {
namespace {

using test::add_straight;
using test::byte;
using test::make_bundled;
using test::px;

RenderParams flat_lines() {
  RenderParams p;
  p.width = 256;
  p.style = Style::lines;
  p.color = ColorBy::flat;
  p.alpha = 1;
  return p;
}

/// c(t) of CUBu's cushion, written out.
double c_of(double t) {
  return 0.2 + 0.8 * std::sqrt(1 - 2 * std::fabs(t - 0.5));
}

void expect_near_px(const std::array<int, 4>& got, std::array<int, 4> want, int tol = 1) {
  for (int c = 0; c < 4; ++c) EXPECT_NEAR(got[c], want[c], tol) << "channel " << c;
}

TEST(RenderFormulas, RainbowHsvCushionLight) {
  auto near = [](const Rgb& a, const Rgb& b) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 1e-12) << c;
  };
  near(rainbow(0), {0, 0, 0.8});     // short: blue
  near(rainbow(0.25), {0, 0.9, 1});  // cyan: w = 1.9
  near(rainbow(0.5), {0, 1, 0});     // green
  near(rainbow(1), {0.8, 0, 0});     // long: red
  EXPECT_EQ(rainbow(-3), rainbow(0));
  EXPECT_EQ(hsv_to_rgb(0, 1, 1), (Rgb{1, 0, 0}));
  EXPECT_EQ(hsv_to_rgb(1.0 / 3, 1, 1), (Rgb{0, 1, 0}));
  EXPECT_EQ(hsv_to_rgb(-1.0 / 3, 1, 1), (Rgb{0, 0, 1}));  // wrapped
  EXPECT_EQ(hsv_to_rgb(0.7, 0, 0.5), (Rgb{0.5, 0.5, 0.5}));
  for (double len : {0.0, 0.3, 1.0})
    for (double t : {0.0, 0.1, 0.5, 0.77, 1.0}) {
      const Cushion c = cushion(len, t);
      EXPECT_DOUBLE_EQ(c.luminance, len + (1 - len) * 0.5 * c_of(t));
      EXPECT_DOUBLE_EQ(c.alpha, (1 - len) + len * 0.5 * c_of(t));
    }
  EXPECT_DOUBLE_EQ(cushion(1, 0.5).alpha, 0.5);  // long edges: half alpha in the middle, 0.1 at the ends
  EXPECT_DOUBLE_EQ(cushion(1, 0).alpha, 0.1);
  // n ∥ l: full light.
  EXPECT_NEAR(light(0.4, 0.4).diffuse, 0.8, 1e-12);
  EXPECT_NEAR(light(0.4, 0.4).specular, 10, 1e-9);
  const double s0 = 1 / std::sqrt(1.32);
  EXPECT_NEAR(light(0, 0).diffuse, 0.1 + 0.7 * s0, 1e-12);
  EXPECT_NEAR(light(0, 0).specular, 10 * std::pow(s0, 8), 1e-9);
  // Light from the upper left: a slope rising toward the lower right faces it.
  EXPECT_GT(light(0.5, 0.5).diffuse, light(0, 0).diffuse);
  EXPECT_GT(light(0, 0).diffuse, light(-0.5, -0.5).diffuse);
  EXPECT_GT(light(0, 1).diffuse, light(0, -1).diffuse);
  EXPECT_EQ(light(-100, -100).diffuse, 0.1);  // facing away: ambient only
}

TEST(Render, CushionAlongALongEdge) {
  Polylines l;
  add_straight(l, 20.5, 100.5, 220.5, 100.5);
  const density::Image img = render_bundle(make_bundled(l), flat_lines());
  ASSERT_EQ(img.width, 256);
  ASSERT_EQ(img.height, 256);
  // One polyline: len = 1, so luminance 1 and alpha 0.5·c(t); grey 0.9 over black.
  for (int x = 21; x < 220; x += 7) {
    const double t = (x + 0.5 - 20.5) / 200;
    const int v = byte(0.9 * 0.5 * c_of(t));
    expect_near_px(px(img, x, 100), {v, v, v, 255});
    expect_near_px(px(img, x, 99), {0, 0, 0, 255}, 0);  // 1 px wide: the rows beside get nothing
    expect_near_px(px(img, x, 101), {0, 0, 0, 255}, 0);
  }
}

TEST(Render, LineWidthAndAntiAliasing) {
  Polylines l;
  add_straight(l, 20.5, 100.5, 220.5, 100.5);  // along pixel centres
  add_straight(l, 20.5, 160, 220.5, 160);      // on the edge between rows 159 and 160
  RenderParams p = flat_lines();
  p.line_width = 3;
  const density::Image img = render_bundle(make_bundled(l), p);
  const int v = px(img, 120, 100)[0];
  EXPECT_GT(v, 0);
  for (int y : {99, 101}) EXPECT_EQ(px(img, 120, y)[0], v);  // 3 px fully covered
  for (int y : {98, 102}) EXPECT_EQ(px(img, 120, y)[0], 0);
  p.line_width = 1;
  const density::Image thin = render_bundle(make_bundled(l), p);
  // Between two rows: each gets coverage 1/2 of the line's alpha.
  const double a = 0.5 * c_of((120.5 - 20.5) / 200);
  EXPECT_NEAR(px(thin, 120, 159)[0], 255 * 0.9 * a * 0.5, 1.0);
  EXPECT_EQ(px(thin, 120, 159), px(thin, 120, 160));
}

TEST(Render, ShortEdgesVaryInLuminanceLongOnesInAlpha) {
  Polylines l;
  add_straight(l, 20.5, 50.5, 70.5, 50.5);     // 50 px: len 0
  add_straight(l, 20.5, 150.5, 220.5, 150.5);  // 200 px: len 1
  const density::Image img = render_bundle(make_bundled(l), flat_lines());
  for (int x = 21; x < 70; x += 5) {
    const double t = (x + 0.5 - 20.5) / 50;
    const int v = byte(0.9 * 0.5 * c_of(t));  // luminance 0.5·c, alpha 1
    expect_near_px(px(img, x, 50), {v, v, v, 255});
  }
  // Alpha modes: `value` hides the shortest edge (value 0), `inverse` the longest.
  RenderParams p = flat_lines();
  p.alpha_mode = AlphaMode::value;
  const density::Image val = render_bundle(make_bundled(l), p);
  expect_near_px(px(val, 45, 50), {0, 0, 0, 255}, 0);
  EXPECT_EQ(px(val, 120, 150), px(img, 120, 150));
  p.alpha_mode = AlphaMode::inverse;
  const density::Image inv = render_bundle(make_bundled(l), p);
  EXPECT_EQ(px(inv, 45, 50), px(img, 45, 50));
  expect_near_px(px(inv, 120, 150), {0, 0, 0, 255}, 0);
  // Global alpha scales the alpha.
  p.alpha_mode = AlphaMode::constant;
  p.alpha = 0.5;
  const density::Image half = render_bundle(make_bundled(l), p);
  const int v = byte(0.9 * 0.5 * 0.5 * c_of(0.5));  // long edge middle: alpha 0.5·0.5·c
  expect_near_px(px(half, 120, 150), {v, v, v, 255});
}

TEST(Render, LongerEdgesAreDrawnOverShorterOnes) {
  Polylines l;
  add_straight(l, 20.5, 150.5, 220.5, 150.5);   // long, listed first
  add_straight(l, 120.5, 130.5, 120.5, 170.5);  // short, crosses it at (120, 150)
  RenderParams p = flat_lines();
  p.color = ColorBy::length;
  const density::Image img = render_bundle(make_bundled(l), p);
  // Short (len 0, t = 0.5): rainbow(0)·0.5 luminance, alpha 1. Long (len 1, t = 0.5): rainbow(1), alpha 0.5.
  const Rgb s = rainbow(0), g = rainbow(1);
  const double a_long = 0.5;
  Rgb under{};  // long over short
  for (int c = 0; c < 3; ++c) under[c] = g[c] * a_long + s[c] * 0.5 * (1 - a_long);
  expect_near_px(px(img, 120, 150), {byte(under[0]), byte(under[1]), byte(under[2]), 255});
}

TEST(Render, Backgrounds) {
  Polylines l;
  add_straight(l, 20.5, 100.5, 220.5, 100.5);
  RenderParams p = flat_lines();
  const density::Image black = render_bundle(make_bundled(l), p);
  expect_near_px(px(black, 5, 5), {0, 0, 0, 255}, 0);
  p.background = "white";
  const density::Image white = render_bundle(make_bundled(l), p);
  expect_near_px(px(white, 5, 5), {255, 255, 255, 255}, 0);
  const double a = 0.5 * c_of((120.5 - 20.5) / 200), v = 0.9 * a + 1 - a;
  expect_near_px(px(white, 120, 100), {byte(v), byte(v), byte(v), 255});
  p.background = "transparent";
  const density::Image clear = render_bundle(make_bundled(l), p);
  expect_near_px(px(clear, 5, 5), {0, 0, 0, 0}, 0);
  expect_near_px(px(clear, 120, 100), {byte(0.9), byte(0.9), byte(0.9), byte(a)});  // straight alpha
}

TEST(Render, AnEmptyBundleIsTheBackground) {
  RenderParams p = flat_lines();
  p.background = "white";
  const density::Image img = render_bundle(make_bundled(Polylines{}), p);
  ASSERT_EQ(img.rgba.size(), 256u * 256u * 4u);
  for (std::uint8_t v : img.rgba) ASSERT_EQ(v, 255);
}

TEST(Render, DirectionColoursByHueOfTheEdgeAngle) {
  Polylines l;
  add_straight(l, 20.5, 30.5, 220.5, 30.5);    // east: angle 0 → red
  add_straight(l, 240.5, 20.5, 240.5, 220.5);  // south (y down): angle π/2 → hue 0.25
  RenderParams p = flat_lines();
  p.color = ColorBy::direction;
  const density::Image img = render_bundle(make_bundled(l), p);
  // Equal lengths: len 1, saturation 1, luminance 1, alpha 0.5·c = 0.5 in the middle.
  expect_near_px(px(img, 120, 30), {byte(0.5), 0, 0, 255});
  const Rgb h = hsv_to_rgb(0.25, 1, 1);
  expect_near_px(px(img, 240, 120), {byte(0.5 * h[0]), byte(0.5 * h[1]), byte(0.5 * h[2]), 255});
}

TEST(Render, DensityAndDisplacementUseTheColourMap) {
  const auto& viridis = density::colormap("viridis").rgb;
  Polylines l;
  add_straight(l, 20.5, 100.5, 220.5, 100.5);
  RenderParams p = flat_lines();
  p.color = ColorBy::density;
  const density::Image img = render_bundle(make_bundled(l), p);
  // A lone line is its own local maximum: ρn = 1 on it; luminance 1, alpha 0.5·c.
  const auto& top = viridis[255];
  expect_near_px(px(img, 120, 100),
                 {byte(0.5 * top[0] / 255.0), byte(0.5 * top[1] / 255.0), byte(0.5 * top[2] / 255.0), 255});

  // Interior points moved 20 px off a 200 px edge: d = 20 / (0.2 · 200) = 0.5.
  Polylines orig, moved;
  add_straight(orig, 20.5, 100.5, 220.5, 100.5);
  moved = orig;
  for (std::size_t k = 1; k + 1 < moved.points(); ++k) moved.y[k] += 20;
  p.color = ColorBy::displacement;
  p.cmap = "magma";
  const density::Image d = render_bundle(make_bundled(moved, 256, &orig), p);
  const auto& mid = density::colormap("magma").rgb[128];  // round(0.5 · 255)
  expect_near_px(px(d, 120, 120),
                 {byte(0.5 * mid[0] / 255.0), byte(0.5 * mid[1] / 255.0), byte(0.5 * mid[2] / 255.0), 255});
}

/// Ten identical lines at y = 60.5 and one lone line at y = 140.5.
Bundled bundle_and_single() {
  Polylines l;
  for (int k = 0; k < 10; ++k) add_straight(l, 20.5, 60.5, 220.5, 60.5);
  add_straight(l, 20.5, 140.5, 220.5, 140.5);
  return make_bundled(l);
}

TEST(Render, TubeScalesByTheLocallyNormalisedDensity) {
  const Bundled b = bundle_and_single();
  RenderParams p = flat_lines();
  const density::Image lines = render_bundle(b, p);
  p.style = Style::tube;
  p.local_max_radius = 16;  // the lone line is 80 px from the bundle: its own maximum
  const density::Image near = render_bundle(b, p);
  EXPECT_EQ(px(near, 120, 140), px(lines, 120, 140));
  EXPECT_EQ(px(near, 120, 60), px(lines, 120, 60));
  p.local_max_radius = 100;  // now the bundle's 10 passes are its maximum: ρn = 1/10
  const density::Image far = render_bundle(b, p);
  EXPECT_NEAR(px(far, 120, 140)[0], px(lines, 120, 140)[0] / 10.0, 1.0);
  EXPECT_EQ(px(far, 120, 60), px(lines, 120, 60));

  // alpha_by_density multiplies alpha by ρn^0.3.
  p.style = Style::lines;
  p.alpha_by_density = true;
  const density::Image faded = render_bundle(b, p);
  const double a = 0.5 * c_of((120.5 - 20.5) / 200);
  EXPECT_NEAR(px(faded, 120, 140)[0], 255 * 0.9 * a * std::pow(0.1, 0.3), 1.0);
}

TEST(Render, TheLocalMaximumIsTakenOverASquare) {
  // The lone line starts 13 px right of and 12 px below the end of a 10-line bundle: inside the square
  // |dx|, |dy| <= 16 (so normalised by the bundle: dim) though 17.7 px away (outside a disc of 16).
  Polylines l;
  for (int k = 0; k < 10; ++k) add_straight(l, 20.5, 60.5, 100.5, 60.5);
  add_straight(l, 112.5, 72.5, 220.5, 72.5);
  RenderParams p = flat_lines();
  const density::Image lines = render_bundle(make_bundled(l), p);
  p.style = Style::tube;  // = lines · ρn
  const density::Image tube = render_bundle(make_bundled(l), p);
  EXPECT_GT(px(lines, 113, 72)[0], 20);
  EXPECT_LT(px(tube, 113, 72)[0] * 3, px(lines, 113, 72)[0]);  // ρn < 1/3: the bundle's maximum
  EXPECT_EQ(px(tube, 150, 72), px(lines, 150, 72));            // ρn = 1: its own maximum
}

TEST(Render, ShadedBundlesAreLitFromTheUpperLeft) {
  Polylines l;
  for (int k = 0; k < 9; ++k) add_straight(l, 20.5, 96.5 + k, 220.5, 96.5 + k);
  RenderParams p = flat_lines();
  p.style = Style::shaded;
  const density::Image img = render_bundle(make_bundled(l), p);
  auto sum = [&](int y) {
    const auto v = px(img, 120, y);
    return v[0] + v[1] + v[2];
  };
  EXPECT_GT(sum(97), sum(103));  // the upper flank faces the light, the lower one turns away
  EXPECT_GT(sum(96), sum(104));
  // The flat top is a specular highlight: white at the line's alpha (0.5 in the middle of a long edge).
  expect_near_px(px(img, 120, 100), {128, 128, 128, 255}, 0);
}

TEST(Render, RelaxationOneDrawsTheOriginalEdges) {
  Polylines orig, moved;
  add_straight(orig, 20.5, 100.5, 220.5, 100.5, 10);
  moved = orig;
  for (std::size_t k = 1; k + 1 < moved.points(); ++k) moved.y[k] += 15;
  RenderParams p = flat_lines();
  auto mask = [](const density::Image& img) {
    std::vector<bool> m;
    for (std::size_t i = 0; i < img.rgba.size(); i += 4) m.push_back(img.rgba[i] > 0);
    return m;
  };
  p.relaxation = 1;
  const Bundled moved_b = make_bundled(moved, 256, &orig);
  EXPECT_EQ(mask(render_bundle(moved_b, p)), mask(render_bundle(make_bundled(orig), p)));
  p.relaxation = -1;  // the bundle's own (0): bundled
  EXPECT_EQ(mask(render_bundle(moved_b, p)), mask(render_bundle(make_bundled(moved), p)));
  EXPECT_NE(mask(render_bundle(moved_b, p)), mask(render_bundle(make_bundled(orig), p)));
}

TEST(Render, AnySizeAndViewports) {
  Polylines l;
  add_straight(l, 20.5, 100.5, 220.5, 100.5);
  RenderParams p = flat_lines();
  p.width = 100;
  const density::Image small = render_bundle(make_bundled(l), p);
  ASSERT_EQ(small.width, 100);
  ASSERT_EQ(small.height, 100);
  const int row = static_cast<int>(100.5 * 100 / 256);  // 39
  EXPECT_GT(px(small, 50, row)[0], 0);
  EXPECT_EQ(px(small, 50, row - 2)[0], 0);

  // Fitted frames show the whole square plane; views show their box.
  Polylines box;
  box.add_edge(0, 0, 200, 100);
  Bundled fitted = make_bundled(l);
  fitted.frame = Frame::fit(box, 512, 0.1);
  p.width = 256;
  Viewport v = Viewport::whole(fitted, p);
  EXPECT_EQ(v.width, 256);
  EXPECT_EQ(v.height, 256);
  EXPECT_DOUBLE_EQ(v.scale, 0.5);
  EXPECT_DOUBLE_EQ(v.x0, 0);
  EXPECT_DOUBLE_EQ(v.y0, 0);
  Bundled view = make_bundled(l);
  view.frame = Frame::view(0, 0, 200, 100, 512);
  v = Viewport::whole(view, p);
  EXPECT_EQ(v.height, 128);
  EXPECT_DOUBLE_EQ(v.x0, 0);
  EXPECT_NEAR(v.y0, 128, 1e-9);
  p.height = 64;  // explicit: centred on the box
  v = Viewport::whole(view, p);
  EXPECT_NEAR(v.y0, 256 - 64, 1e-9);  // the box's centre (256) minus half of 64 px at 0.5 px per bundle px
  EXPECT_EQ(render_bundle(view, p).height, 64);
}

TEST(Render, DeterministicBytes) {
  Polylines l;
  for (int k = 0; k < 60; ++k)
    add_straight(l, 10 + 3.7 * k, 20 + (k % 7) * 13.1, 240 - 2.9 * k, 230 - (k % 5) * 17.3, 5);
  for (Style s : {Style::lines, Style::shaded, Style::tube}) {
    RenderParams p;
    p.width = 300;
    p.style = s;
    const Bundled b = make_bundled(l);
    EXPECT_EQ(density::encode_png(render_bundle(b, p)), density::encode_png(render_bundle(b, p)));
  }
}

TEST(Render, ParametersAreValidatedByName) {
  auto param_of = [](auto&& f) {
    try {
      f();
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), Error::Kind::invalid_argument);
      return e.param() + ": " + e.what();
    }
    return std::string("no error");
  };
  RenderParams p;
  p.width = 10;
  EXPECT_EQ(param_of([&] { p.validate(); }), "width: width 10 is outside 16..8192");
  p = RenderParams{};
  EXPECT_EQ(param_of([&] { p.set("style", "fancy"); }),
            "style: style 'fancy' is not one of lines, shaded, tube");
  EXPECT_EQ(param_of([&] { p.set("alpha", "1.5"); }), "alpha: alpha 1.5 is outside 0..1");
  EXPECT_EQ(param_of([&] { p.set("alpha", "x"); }), "alpha: alpha 'x' is not a number");
  EXPECT_EQ(param_of([&] { p.set("colour", "flat"); }), "colour: unknown render parameter 'colour'");
  EXPECT_EQ(param_of([&] { p.set("background", "red"); }),
            "background: background 'red' is not one of black, white, transparent");
  p = RenderParams{};
  EXPECT_EQ(param_of([&] { p.set("cmap", "rainbow"); }).substr(0, 6), "cmap: ");
  p = RenderParams{};
  p.set("color", "direction");
  p.set("alpha_by_density", "true");
  p.set("local_max_radius", "8");
  EXPECT_EQ(p.color, ColorBy::direction);
  EXPECT_TRUE(p.alpha_by_density);
  EXPECT_EQ(p.local_max_radius, 8);
  for (ColorBy c :
       {ColorBy::length, ColorBy::direction, ColorBy::density, ColorBy::displacement, ColorBy::flat})
    EXPECT_EQ(parse_color_by(to_string(c)), c);
  for (AlphaMode a : {AlphaMode::constant, AlphaMode::value, AlphaMode::inverse})
    EXPECT_EQ(parse_alpha_mode(to_string(a)), a);
}

}  // namespace
}  // namespace trailscope::bundling
