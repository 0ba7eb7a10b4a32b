// Flow maps end to end (trailscope/flow/flow_map.hpp, render.hpp): the levels' geometry, the blending
// rules checked pixel by pixel, golden images of the Europe SO6 day and of an analytic uploaded field.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "golden.hpp"
#include "test_support.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/flow/render.hpp"
#include "trailscope/ingest/ingest.hpp"

namespace trailscope::flow {
namespace {

const TrailSet& europe() {
  static const std::unique_ptr<TrailSet> ts = [] {
    const auto path = test::shared_data("flights/traffic_europe_20180101_m3.so6.gz");
    return std::make_unique<TrailSet>(ingest::ingest_file(path.string()));
  }();
  return *ts;
}

/// A vortex beside a saddle, as an uploaded field (proto/flow_field.md).
std::string vortex_saddle_json(int w, int h) {
  nlohmann::json u = nlohmann::json::array(), v = nlohmann::json::array();
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const double x = (i + 0.5) / w * 2 - 1, y = 1 - (j + 0.5) / h * 2;  // y up
      const double vx = -(y - 0.0) * std::exp(-4 * ((x + 0.5) * (x + 0.5) + y * y)) + (x - 0.5) * 0.6;
      const double vy = (x + 0.5) * std::exp(-4 * ((x + 0.5) * (x + 0.5) + y * y)) - y * 0.6;
      u.push_back(vx), v.push_back(vy);
    }
  return nlohmann::json{
      {"format", "trailscope-flow-field"}, {"version", 1}, {"width", w}, {"height", h}, {"u", u}, {"v", v}}
      .dump();
}

FlowParams field_params() {
  FlowParams p;
  p.lines.min_traffic = 0.01;
  p.lines.min_coherence = 0;
  p.lines.d_sep = 3;
  return p;
}

/// Distance from (x, y) to polyline l of `pl`.
double distance_to(const bundling::Polylines& pl, std::size_t l, double x, double y) {
  double best = 1e300;
  for (std::size_t k = pl.begin(l); k + 1 < pl.end(l); ++k) {
    const double ax = pl.x[k], ay = pl.y[k], dx = pl.x[k + 1] - ax, dy = pl.y[k + 1] - ay;
    const double len2 = dx * dx + dy * dy;
    const double t = len2 > 0 ? std::clamp(((x - ax) * dx + (y - ay) * dy) / len2, 0.0, 1.0) : 0;
    best = std::min(best, std::hypot(ax + t * dx - x, ay + t * dy - y));
  }
  return best;
}

TEST(FlowMap, LevelsInterpolateFromStreamlinesToBundles) {
  const FlowMap m = flow_map(parse_field(vortex_saddle_json(64, 48)), field_params(), Backend::cpu);
  ASSERT_GT(m.lines.size(), 10u);
  ASSERT_TRUE(m.has_bundle);
  ASSERT_EQ(m.sector.size(), m.lines.size());
  ASSERT_EQ(m.line_traffic.size(), m.lines.size());
  // Levels 0..1 draw the streamlines themselves.
  EXPECT_EQ(m.lines_at(0.3).x, m.lines.x);
  EXPECT_EQ(m.lines_at(1).x, m.lines.x);
  // Just above 1 the relaxed bundle lies on the streamlines (CUBu relaxation 1 = the input, resampled).
  const bundling::Polylines near1 = m.lines_at(1.0 + 1e-9);
  ASSERT_EQ(near1.size(), m.lines.size());
  double worst = 0;
  for (std::size_t l = 0; l < near1.size(); ++l)
    for (std::size_t k = near1.begin(l); k < near1.end(l); ++k)
      worst = std::max(worst, distance_to(m.lines, l, near1.x[k], near1.y[k]));
  EXPECT_LT(worst, 1e-3) << "cells";
  // Level 2 is the bundle, which moved the lines.
  const bundling::Polylines b = m.lines_at(2);
  double moved = 0;
  for (std::size_t l = 0; l < b.size(); ++l)
    for (std::size_t k = b.begin(l); k < b.end(l); ++k)
      moved = std::max(moved, distance_to(m.lines, l, b.x[k], b.y[k]));
  EXPECT_GT(moved, 0.5) << "cells";
  EXPECT_THROW(m.lines_at(2.5), Error);
}

TEST(FlowRender, LevelZeroIsTheDensityAndLevelOneHidesIt) {
  const FlowMap m = flow_map(parse_field(vortex_saddle_json(40, 30)), field_params(), Backend::cpu);
  FlowRenderParams rp;
  rp.cell_px = 3;
  const density::Image base = field_base(m, rp);
  ASSERT_EQ(base.width, 120);
  ASSERT_EQ(base.height, 90);
  rp.level = 0;
  const density::Image l0 = render_flow(m, base, rp);
  // Level 0: the density over black, nothing else (the lines' opacity is 0).
  for (std::size_t p = 0; p < l0.rgba.size() / 4; ++p) {
    const double a = base.rgba[4 * p + 3] / 255.0;
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(l0.rgba[4 * p + c], base.rgba[4 * p + c] * a, 0.51) << p;
    ASSERT_EQ(l0.rgba[4 * p + 3], 255);
  }
  // Level 1: black wherever no line reaches (the density is gone).
  rp.level = 1;
  const density::Image l1 = render_flow(m, base, rp);
  std::size_t lit = 0;
  for (int y = 0; y < l1.height; ++y)
    for (int x = 0; x < l1.width; ++x) {
      const std::uint8_t* px = l1.pixel(x, y);
      const bool any = px[0] || px[1] || px[2];
      lit += any;
      if (!any) continue;
      double d = 1e300;
      for (std::size_t l = 0; l < m.lines.size(); ++l)
        d = std::min(d, distance_to(m.lines, l, (x + 0.5) / rp.cell_px, (y + 0.5) / rp.cell_px) * rp.cell_px);
      ASSERT_LE(d, 0.5 * rp.line_width * 2 + 0.5 + 1e-9)
          << "pixel " << x << "," << y << " lit far from every line";
    }
  EXPECT_GT(lit, 500u);
  // Level 0.5: the halo clears the density next to the lines, so pixels there are darker than the base.
  rp.level = 0.5;
  const density::Image lh = render_flow(m, base, rp);
  EXPECT_NE(lh.rgba, l0.rgba);
  EXPECT_NE(lh.rgba, l1.rgba);
  // Transparent background: no line and no density means alpha 0.
  rp.level = 1, rp.background = "transparent";
  const density::Image lt = render_flow(m, base, rp);
  for (std::size_t p = 0; p < lt.rgba.size() / 4; ++p)
    if (!l1.rgba[4 * p] && !l1.rgba[4 * p + 1] && !l1.rgba[4 * p + 2]) ASSERT_EQ(lt.rgba[4 * p + 3], 0);
}

TEST(FlowRender, BadParametersNameThemselves) {
  FlowRenderParams rp;
  FlowParams p;
  const auto param_of = [&](const char* n, const char* v) {
    try {
      set_flow_option(p, rp, n, v);
    } catch (const Error& e) {
      return e.param();
    }
    return std::string("none");
  };
  EXPECT_EQ(param_of("level", "2.5"), "level");
  EXPECT_EQ(param_of("cell_px", "0"), "cell_px");
  EXPECT_EQ(param_of("background", "pink"), "background");
  EXPECT_EQ(param_of("cmap", "nope"), "cmap");
  EXPECT_EQ(param_of("grid", "2000"), "grid");
  EXPECT_EQ(param_of("d_sep", "x"), "d_sep");
  EXPECT_EQ(param_of("bundle.h", "1000"), "h");
  EXPECT_EQ(param_of("colour", "1"), "colour");
  EXPECT_EQ(param_of("level", "1.5"), "none");
  EXPECT_EQ(rp.level, 1.5);
  // The cost is refused before any work: a fine grid with dense lines.
  p = FlowParams{};
  p.field.grid = 1024, p.field.sectors = 16, p.lines.d_sep = 0.5, p.lines.step = 0.05;
  try {
    p.check_cost(1024, 1024, 16);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::payload_too_large);
    EXPECT_EQ(e.param(), "d_sep");
  }
  FlowParams ok;
  EXPECT_NO_THROW(ok.check_cost(256, 256, 8));  // the defaults fit
}

TEST(FlowGolden, UploadedVortexAndSaddle) {
  FlowRenderParams rp;
  rp.level = 1.5;
  const FlowImage r = flow_image(parse_field(vortex_saddle_json(96, 64)), field_params(), rp, Backend::cpu);
  test::compare_with_golden(r.image, "flow_field_vortex_saddle_level1_5.png");
}

class FlowEurope : public ::testing::Test {
 protected:
  static FlowImage at(double level) {
    FlowParams p;
    p.field.grid = 160;
    FlowRenderParams rp;
    rp.level = level;
    rp.cell_px = 4;
    Query q;
    q.bbox = BBox{-12, 35, 30, 62};
    return flow_image(europe(), q, p, rp, Backend::cpu);
  }
};

TEST_F(FlowEurope, SeparationHoldsInEverySector) {
  FlowParams p;
  p.field.grid = 160;
  Query q;
  q.bbox = BBox{-12, 35, 30, 62};
  const FlowMap m = flow_map(europe(), q, p, Backend::cpu);
  ASSERT_GT(m.lines.size(), 100u);
  const double d_test = p.lines.d_test * p.lines.d_sep;
  // Brute force over every pair of points of two lines of the same sector.
  for (int s = 0; s < p.field.sectors; ++s) {
    std::vector<std::size_t> ls;
    for (std::size_t l = 0; l < m.lines.size(); ++l)
      if (m.sector[l] == s) ls.push_back(l);
    EXPECT_GT(ls.size(), 3u) << "sector " << s;
    double worst = 1e300;
    for (std::size_t a = 0; a < ls.size(); ++a)
      for (std::size_t b = a + 1; b < ls.size(); ++b)
        for (std::size_t i = m.lines.begin(ls[a]); i < m.lines.end(ls[a]); ++i)
          for (std::size_t k = m.lines.begin(ls[b]); k < m.lines.end(ls[b]); ++k)
            worst = std::min(worst, std::hypot(m.lines.x[i] - m.lines.x[k], m.lines.y[i] - m.lines.y[k]));
    EXPECT_GE(worst, d_test - 1e-9) << "sector " << s;
  }
  // Lines run with the traffic of their sector: the mean step heading lies within the sector.
  for (std::size_t l = 0; l < m.lines.size(); ++l) {
    const std::size_t b = m.lines.begin(l), e = m.lines.end(l) - 1;
    const double dx = m.lines.x[e] - m.lines.x[b], dy = m.lines.y[e] - m.lines.y[b];
    if (std::hypot(dx, dy) < 4 * p.lines.d_sep) continue;  // short or curled lines say little
    double heading = std::atan2(dx, -dy) * 180 / M_PI;
    const double centre = m.field.sector_heading(m.sector[l]);
    EXPECT_LT(std::abs(std::remainder(heading - centre, 360.0)), 90) << "line " << l;
  }
}

TEST_F(FlowEurope, GoldenLevels) {
  for (const auto& [level, name] :
       {std::pair{0.5, "flow_europe_level0_5.png"}, std::pair{1.0, "flow_europe_level1.png"},
        std::pair{2.0, "flow_europe_level2.png"}}) {
    SCOPED_TRACE(name);
    test::compare_with_golden(at(level).image, name);
  }
}

}  // namespace
}  // namespace trailscope::flow
