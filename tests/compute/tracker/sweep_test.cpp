#include <gtest/gtest.h>

#include <set>

#include "trailscope/core/error.hpp"
#include "trailscope/tracker/sweep.hpp"

namespace trailscope::tracker {
namespace {

TEST(Sweep, GridIsTheProductWithTheLastAxisFastest) {
  SweepSpec s;
  s.mode = SweepMode::grid;
  s.axes = {{"ncc_min", 0.2, 0.6, 3}, {"n_lost", 2, 6, 3}};
  const auto pts = sweep_points(s);
  ASSERT_EQ(pts.size(), 9u);
  EXPECT_DOUBLE_EQ(pts[0].ncc_min, 0.2);
  EXPECT_EQ(pts[0].n_lost, 2);
  EXPECT_EQ(pts[1].n_lost, 4);
  EXPECT_DOUBLE_EQ(pts[3].ncc_min, 0.4);
  EXPECT_EQ(pts[8].n_lost, 6);
  EXPECT_EQ(pts[8].d_gate_mm, TrackerParams{}.d_gate_mm);  // untouched parameters keep the base
}

TEST(Sweep, RandomPointsAreSeededInRangeAndRespectConstraints) {
  SweepSpec s;
  s.samples = 300;
  s.axes = {{"r_min_mm", 4, 12}, {"r_max_mm", 8, 20}, {"median_k", 1, 5}, {"n_confirm", 1, 3}};
  const auto a = sweep_points(s), b = sweep_points(s);
  ASSERT_EQ(a.size(), 300u);
  std::set<int> ks, confirms;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(to_vector(a[i]), to_vector(b[i]));
    EXPECT_LT(a[i].r_min_mm, a[i].r_max_mm);
    EXPECT_NO_THROW(validate(a[i]));
    ks.insert(a[i].median_k);
    confirms.insert(a[i].n_confirm);
  }
  EXPECT_EQ(ks, (std::set<int>{1, 3, 5}));  // 4 and 2 are drawn again (median_k must be odd)
  EXPECT_EQ(confirms, (std::set<int>{1, 2, 3}));
  s.seed = 2;
  EXPECT_NE(to_vector(sweep_points(s)[0]), to_vector(a[0]));
}

TEST(Sweep, BadSpecsNameTheField) {
  const auto expect = [](const nlohmann::json& j, const std::string& param, const std::string& msg) {
    try {
      sweep_points(parse_sweep(j));
      FAIL() << j.dump();
    } catch (const Error& e) {
      EXPECT_EQ(e.param(), param) << j.dump();
      EXPECT_EQ(std::string(e.what()), msg);
    }
  };
  expect({{"axes", {{{"param", "ncc"}}}}}, "axes", "unknown tracker parameter 'ncc' in axes");
  expect({{"axes", nlohmann::json::array()}}, "axes", "a sweep needs at least one axis");
  expect({{"axes", {{{"param", "ncc_min"}, {"min", 0.5}, {"max", 2}}}}}, "axes",
         "axis ncc_min must lie within [0, 1] with min <= max, got [0.5, 2]");
  expect({{"mode", "grid"}, {"axes", {{{"param", "ncc_min"}, {"steps", 1}}}}}, "axes",
         "axis ncc_min needs 2..100 steps, got 1");
  expect({{"mode", "grid"},
          {"axes", {{{"param", "ncc_min"}, {"steps", 100}}, {{"param", "n_lost"}, {"steps", 100}}}}},
         "axes", "the grid has 10000 points, at most 5000");
  expect({{"mode", "spiral"}, {"axes", {{{"param", "ncc_min"}}}}}, "mode",
         "mode must be \"grid\" or \"random\"");
  expect({{"samples", 0}, {"axes", {{{"param", "ncc_min"}}}}}, "samples",
         "samples must be a positive whole number");
  expect({{"base", {{"ncc_min", 3}}}, {"axes", {{{"param", "n_lost"}}}}}, "ncc_min",
         "ncc_min must be in [0, 1], got 3");
  const auto round =
      parse_sweep(to_json(parse_sweep({{"mode", "grid"}, {"axes", {{{"param", "ncc_min"}, {"steps", 4}}}}})));
  EXPECT_EQ(round.mode, SweepMode::grid);
  EXPECT_EQ(round.axes[0].steps, 4);
}

}  // namespace
}  // namespace trailscope::tracker
