#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "trailscope/analysis/importance.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::analysis {
namespace {

TEST(Importance, CorrelationsMatchHandComputedValues) {
  // x = 1..5, y = 2, 4, 5, 4, 5: r = 6 / sqrt(10 * 6) by hand (deviations -2..2 and -2, 0, 1, 0, 1).
  const std::vector<double> a{1, 2, 3, 4, 5}, b{2, 4, 5, 4, 5};
  EXPECT_NEAR(pearson(a, b), 6.0 / std::sqrt(60.0), 1e-12);
  EXPECT_EQ(ranks(b), (std::vector<double>{1, 2.5, 4.5, 2.5, 4.5}));
  EXPECT_TRUE(std::isnan(pearson(a, {3, 3, 3, 3, 3})));
}

TEST(Importance, TheForestFindsTheParameterThatMatters) {
  // y depends on x0 (strongly, non-monotonically: a valley) and x1 (weakly); x2..x4 are noise. A
  // correlation sees little of x0 (the valley is symmetric); the forest must rank it first.
  std::mt19937_64 gen(7);
  std::uniform_real_distribution<double> u(-1, 1);
  std::normal_distribution<double> noise(0, 0.05);
  const std::vector<std::string> names{"x0", "x1", "x2", "x3", "x4"};
  std::vector<double> x, y;
  for (int i = 0; i < 400; ++i) {
    std::vector<double> r(5);
    for (auto& v : r) v = u(gen);
    x.insert(x.end(), r.begin(), r.end());
    y.push_back(3 * r[0] * r[0] + 0.5 * r[1] + noise(gen));
  }
  const auto res = parameter_importance(x, names, y);
  ASSERT_EQ(res.inputs.size(), 5u);
  EXPECT_GT(res.inputs[0].forest, 0.7);
  EXPECT_GT(res.inputs[1].forest, res.inputs[2].forest);
  double sum = 0;
  for (const auto& in : res.inputs) sum += in.forest;
  EXPECT_NEAR(sum, 1.0, 1e-9);
  EXPECT_LT(std::fabs(res.inputs[0].pearson), 0.2);  // the valley hides from a linear view
  EXPECT_GT(res.inputs[1].pearson, 0.1);
  EXPECT_GT(res.forest_r2, 0.8);
  EXPECT_EQ(res.samples, 400u);
  // Deterministic for a seed.
  const auto again = parameter_importance(x, names, y);
  EXPECT_EQ(again.inputs[0].forest, res.inputs[0].forest);
}

TEST(Importance, SkipsRunsWithoutAnOutputAndRejectsBadInput) {
  const std::vector<std::string> names{"a"};
  const std::vector<double> x{1, 2, 3, 4, 5};
  const std::vector<double> y{1, NAN, 3, 4, 5};
  EXPECT_EQ(parameter_importance(x, names, y).samples, 4u);
  try {
    parameter_importance({1, 2, 3}, names, {1, 2, 3, 4});
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.param(), "x");
    EXPECT_STREQ(e.what(), "x must hold 4 rows of 1 inputs, got 3 values");
  }
  try {
    parameter_importance({1, 2, 3, 4}, names, {1, NAN, NAN, 4});
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::unprocessable);
    EXPECT_STREQ(e.what(), "importance needs at least 4 samples with a finite output, got 2");
  }
  try {
    parameter_importance({1, 2, INFINITY, 4}, names, {1, 2, 3, 4});
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "input 'a' of sample 2 is not a finite number");
  }
  ForestOptions o;
  o.trees = 0;
  try {
    parameter_importance(x, names, {1, 2, 3, 4, 5}, o);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.param(), "trees");
    EXPECT_STREQ(e.what(), "trees must be in [1, 1000]");
  }
}

}  // namespace
}  // namespace trailscope::analysis
