// Shading on known arrays: the three `how` normalisations, the colormap tables against the published
// end and middle colours, transparency, the alpha ramp, and PNG round trips.
#include "trailscope/density/shade.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "trailscope/core/error.hpp"
#include "trailscope/density/colormap.hpp"
#include "trailscope/density/png.hpp"
#include "trailscope/density/span.hpp"

namespace trailscope::density {
namespace {

Raster raster(std::vector<float> v, int w = 0) {
  Raster r;
  r.width = w ? w : static_cast<int>(v.size());
  r.height = static_cast<int>(v.size()) / r.width;
  r.values = std::move(v);
  return r;
}

TEST(Span, LinearAndLogOnKnownValues) {
  const SpanStats s = compute_span(raster({1, 2, 3, 4, NAN}));
  EXPECT_FALSE(s.empty);
  EXPECT_EQ(s.samples, 4u);
  EXPECT_DOUBLE_EQ(s.lo, 1);
  EXPECT_DOUBLE_EQ(s.hi, 4);
  EXPECT_DOUBLE_EQ(s.normalize(1, How::linear), 0.0);
  EXPECT_DOUBLE_EQ(s.normalize(2, How::linear), 1.0 / 3);
  EXPECT_DOUBLE_EQ(s.normalize(4, How::linear), 1.0);
  EXPECT_DOUBLE_EQ(s.normalize(9, How::linear), 1.0);  // beyond the span: clamped
  EXPECT_DOUBLE_EQ(s.normalize(0.5, How::linear), 0.0);
  // Datashader's log: log1p of the value, between log1p(lo) and log1p(hi).
  EXPECT_NEAR(s.normalize(2, How::log), (std::log(3.0) - std::log(2.0)) / (std::log(5.0) - std::log(2.0)),
              1e-15);
  EXPECT_TRUE(std::isnan(s.normalize(NAN, How::log)));
  // Data below zero is shifted so that log1p stays defined.
  const SpanStats n = compute_span(raster({-3, 0, 5}));
  EXPECT_NEAR(n.normalize(0, How::log), std::log1p(3.0) / std::log1p(8.0), 1e-15);
}

TEST(Span, EqHistOnKnownValues) {
  // Samples 1, 1, 2, 4: F(1) = 1/2, F(2) = 3/4, F(4) = 1; rescaled so that lo → 0 and hi → 1.
  const SpanStats s = compute_span(raster({1, 1, 2, 4}));
  ASSERT_EQ(s.cdf_values, (std::vector<double>{1, 2, 4}));
  ASSERT_EQ(s.cdf, (std::vector<double>{0.5, 0.75, 1.0}));
  EXPECT_DOUBLE_EQ(s.normalize(1, How::eq_hist), 0.0);
  EXPECT_DOUBLE_EQ(s.normalize(2, How::eq_hist), 0.5);
  EXPECT_DOUBLE_EQ(s.normalize(3, How::eq_hist), 0.75);  // between 2 and 4: F interpolated to 0.875
  EXPECT_DOUBLE_EQ(s.normalize(4, How::eq_hist), 1.0);
  // Equalisation spreads a skewed distribution evenly: 1000 values of 1..1000 squared.
  std::vector<float> v;
  for (int i = 1; i <= 1000; ++i) v.push_back(static_cast<float>(i * i));
  const SpanStats q = compute_span(raster(v));
  EXPECT_NEAR(q.normalize(500.0 * 500.0, How::eq_hist), 0.5, 0.002);
  EXPECT_LT(q.normalize(500.0 * 500.0, How::linear), 0.26);
}

TEST(Span, ManyDistinctValuesBecomeQuantiles) {
  std::vector<float> v;
  for (int i = 0; i < 100000; ++i) v.push_back(static_cast<float>(i) * 0.25f + 1.0f);
  const SpanStats s = compute_span(raster(v, 1000));
  EXPECT_LE(s.cdf_values.size(), kMaxCdfPoints + 1);
  EXPECT_DOUBLE_EQ(s.cdf.back(), 1.0);
  EXPECT_DOUBLE_EQ(s.cdf_values.back(), s.hi);
  EXPECT_NEAR(s.normalize(s.lo + (s.hi - s.lo) * 0.3, How::eq_hist), 0.3, 0.001);  // uniform data
}

TEST(Span, ScaleAndFloor) {
  const SpanStats s = compute_span(raster({2, 8, 40}), 0.25, 1.0);  // 0.5 → 1, 2, 10
  EXPECT_DOUBLE_EQ(s.lo, 1.0);
  EXPECT_DOUBLE_EQ(s.hi, 10.0);
  const SpanStats e = compute_span(raster({NAN, NAN}));
  EXPECT_TRUE(e.empty);
  EXPECT_DOUBLE_EQ(e.normalize(5, How::eq_hist), 0.0);
}

TEST(Span, RescaleEqualsComputingWithTheScale) {
  const Raster r = raster({1, 1, 2, 3, 3, 3, 8, 20, NAN, 5});
  for (const auto& [scale, floor] : {std::pair{0.25, 1.0}, std::pair{0.5, -1e300}, std::pair{4.0, 0.0}}) {
    const SpanStats a = rescale_span(compute_span(r), scale, floor), b = compute_span(r, scale, floor);
    EXPECT_EQ(a.cdf_values, b.cdf_values);
    EXPECT_EQ(a.cdf, b.cdf);
    EXPECT_EQ(a.lo, b.lo);
    EXPECT_EQ(a.hi, b.hi);
    EXPECT_EQ(a.samples, b.samples);
  }
  EXPECT_TRUE(rescale_span(SpanStats{}, 2.0).empty);
}

TEST(Span, ParsesHow) {
  EXPECT_EQ(parse_how("log"), How::log);
  EXPECT_STREQ(to_string(How::eq_hist), "eq_hist");
  try {
    parse_how("sqrt", "how");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.param(), "how");
  }
}

std::array<std::uint8_t, 3> rgb(std::uint32_t hex) {
  return {static_cast<std::uint8_t>(hex >> 16), static_cast<std::uint8_t>(hex >> 8),
          static_cast<std::uint8_t>(hex)};
}

void expect_near(const std::array<std::uint8_t, 3>& a, const std::array<std::uint8_t, 3>& b, int tol,
                 const char* what) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], tol) << what << " channel " << c;
}

TEST(Colormap, MatchesPublishedColours) {
  // Ends and middles of the published tables (matplotlib's viridis is #440154 → #21918c → #fde725).
  expect_near(colormap("viridis").rgb[0], rgb(0x440154), 0, "viridis 0");
  expect_near(colormap("viridis").rgb[128], rgb(0x21918c), 1, "viridis 128");
  expect_near(colormap("viridis").rgb[255], rgb(0xfde725), 0, "viridis 255");
  expect_near(colormap("magma").rgb[0], rgb(0x000004), 0, "magma 0");
  expect_near(colormap("magma").rgb[255], rgb(0xfcfdbf), 0, "magma 255");
  expect_near(colormap("inferno").rgb[0], rgb(0x000004), 0, "inferno 0");
  expect_near(colormap("inferno").rgb[255], rgb(0xfcffa4), 0, "inferno 255");
  expect_near(colormap("fire").rgb[0], rgb(0x000000), 0, "fire 0");
  expect_near(colormap("fire").rgb[255], rgb(0xffffff), 0, "fire 255");
  // fire row 128 of the CET CSV is (0.93061, 0.08131, 0) → (237, 21, 0).
  expect_near(colormap("fire").rgb[128], {237, 21, 0}, 1, "fire 128");
  expect_near(colormap("gray").rgb[51], {51, 51, 51}, 0, "gray");
  EXPECT_EQ(colormap_names(), (std::vector<std::string>{"fire", "gray", "inferno", "magma", "viridis"}));
  // Perceptually ordered maps get lighter along the table.
  for (const auto& name : {"viridis", "magma", "inferno", "fire", "gray"}) {
    const auto& m = colormap(name).rgb;
    auto luma = [&](int i) { return 0.2126 * m[i][0] + 0.7152 * m[i][1] + 0.0722 * m[i][2]; };
    for (int i = 16; i < 256; i += 16) EXPECT_GT(luma(i), luma(i - 16)) << name << " " << i;
  }
  try {
    colormap("jet");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.param(), "cmap");
    EXPECT_NE(std::string(e.what()).find("viridis"), std::string::npos);
  }
}

TEST(Shade, ColoursTransparencyAndAlphaRamp) {
  const Raster r = raster({NAN, 1, 2, 4}, 2);
  const SpanStats s = compute_span(r);
  ShadeOptions o;
  o.how = How::linear;
  o.cmap = "gray";
  const Image img = shade(r, s, o);
  ASSERT_EQ(img.width, 2);
  ASSERT_EQ(img.height, 2);
  EXPECT_EQ(img.pixel(0, 0)[3], 0);  // no data: transparent
  EXPECT_EQ(img.pixel(1, 0)[0], 0);  // lo → first colour
  EXPECT_EQ(img.pixel(1, 0)[3], 255);
  EXPECT_EQ(img.pixel(0, 1)[0], 85);  // (2−1)/3 · 255
  EXPECT_EQ(img.pixel(1, 1)[0], 255);
  o.alpha_ramp = true;
  o.min_alpha = 40;
  const Image ramp = shade(r, s, o);
  EXPECT_EQ(ramp.pixel(1, 0)[3], 40);
  EXPECT_EQ(ramp.pixel(0, 1)[3], 112);  // 40 + (255−40)/3
  EXPECT_EQ(ramp.pixel(1, 1)[3], 255);
  o.min_alpha = 300;
  EXPECT_THROW(shade(r, s, o), Error);
  o.min_alpha = 40;
  o.cmap = "nope";
  EXPECT_THROW(shade(r, s, o), Error);
}

TEST(Png, RoundTripKeepsStraightAlpha) {
  Image img;
  img.width = 3;
  img.height = 2;
  img.rgba = {255, 0, 0, 255, 10, 200, 30, 128, 0, 0, 0, 0, 1, 2, 3, 4, 250, 251, 252, 1, 9, 9, 9, 255};
  const std::string png = encode_png(img);
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  const Image back = decode_png(png);
  EXPECT_EQ(back.width, 3);
  EXPECT_EQ(back.height, 2);
  EXPECT_EQ(back.rgba, img.rgba);  // colour under partial alpha is untouched (no premultiplication)
  try {
    decode_png("not a png");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::unsupported_format);
  }
}

}  // namespace
}  // namespace trailscope::density
