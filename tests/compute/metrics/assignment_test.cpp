// The Hungarian solver against brute force: exact optimality is what makes the metrics match TrackEval
// (scipy's linear_sum_assignment is exact too).
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "trailscope/core/error.hpp"
#include "trailscope/metrics/assignment.hpp"

namespace trailscope::metrics {
namespace {

/// Minimal cost over all assignments of min(r, c) pairs, by enumerating permutations.
double brute_force_min(const std::vector<double>& cost, int r, int c) {
  const bool wide = r <= c;
  const int small = wide ? r : c, big = wide ? c : r;
  std::vector<int> perm(big);
  std::iota(perm.begin(), perm.end(), 0);
  double best = std::numeric_limits<double>::infinity();
  do {  // the first `small` entries of each permutation of the larger side
    double s = 0;
    for (int i = 0; i < small; ++i) s += wide ? cost[i * c + perm[i]] : cost[perm[i] * c + i];
    best = std::min(best, s);
  } while (std::next_permutation(perm.begin(), perm.end()));
  return best;
}

double cost_of(const std::vector<double>& cost, int c, const std::vector<int>& col_of_row) {
  double s = 0;
  for (std::size_t i = 0; i < col_of_row.size(); ++i)
    if (col_of_row[i] >= 0) s += cost[i * c + col_of_row[i]];
  return s;
}

void expect_valid(const std::vector<int>& col_of_row, int r, int c) {
  std::vector<int> seen(c, 0);
  int assigned = 0;
  for (const int j : col_of_row) {
    if (j < 0) continue;
    ASSERT_LT(j, c);
    EXPECT_EQ(seen[j]++, 0) << "column used twice";
    ++assigned;
  }
  EXPECT_EQ(assigned, std::min(r, c));
}

TEST(LinearSumAssignment, MatchesBruteForceOnRandomMatrices) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 600; ++trial) {
    const int r = 1 + static_cast<int>(rng() % 6), c = 1 + static_cast<int>(rng() % 6);
    std::vector<double> cost(r * c);
    // Every third matrix has small integer costs, which makes many assignments tie.
    const bool ties = trial % 3 == 0;
    std::uniform_real_distribution<double> u(-5.0, 5.0);
    for (auto& v : cost) v = ties ? double(rng() % 3) : u(rng);
    const auto a = linear_sum_assignment(cost, r, c);
    ASSERT_EQ(a.size(), static_cast<std::size_t>(r));
    expect_valid(a, r, c);
    EXPECT_NEAR(cost_of(cost, c, a), brute_force_min(cost, r, c), 1e-9)
        << r << "x" << c << " trial " << trial;
  }
}

TEST(LinearSumAssignment, EdgeCasesAndErrors) {
  EXPECT_TRUE(linear_sum_assignment({}, 0, 0).empty());
  EXPECT_EQ(linear_sum_assignment({}, 3, 0), std::vector<int>(3, -1));
  const std::vector<double> one{4.0};
  EXPECT_EQ(linear_sum_assignment(one, 1, 1), std::vector<int>{0});
  EXPECT_THROW(linear_sum_assignment(one, 2, 1), Error);
  const std::vector<double> nan{std::numeric_limits<double>::quiet_NaN()};
  EXPECT_THROW(linear_sum_assignment(nan, 1, 1), Error);
  // The classic 3x3 example: optimum 5 (0->1, 1->0, 2->2).
  const std::vector<double> m{4, 1, 3, 2, 0, 5, 3, 2, 2};
  EXPECT_EQ(linear_sum_assignment(m, 3, 3), (std::vector<int>{1, 0, 2}));
}

TEST(MaxWeightMatching, MatchesBruteForceOnSparseInputs) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 400; ++trial) {
    const int r = 1 + static_cast<int>(rng() % 6), c = 1 + static_cast<int>(rng() % 6);
    std::vector<WeightedPair> pairs;
    std::vector<double> neg(r * c, 0.0);  // dense -W for the brute force
    for (int i = 0; i < r; ++i)
      for (int j = 0; j < c; ++j)
        if (rng() % 3 == 0) {  // sparse, so that several independent groups form
          const double w = 0.05 + (rng() % 1000) / 1000.0;
          pairs.push_back({i, j, w});
          neg[i * c + j] = -w;
        }
    const auto m = max_weight_matching(r, c, pairs);
    double total = 0;
    std::vector<int> row_used(r, 0), col_used(c, 0);
    for (const auto& [i, j] : m) {
      EXPECT_EQ(row_used[i]++, 0);
      EXPECT_EQ(col_used[j]++, 0);
      EXPECT_LT(neg[i * c + j], 0) << "a matched pair must be a listed pair";
      total -= neg[i * c + j];
    }
    EXPECT_NEAR(total, -brute_force_min(neg, r, c), 1e-9) << "trial " << trial;
    EXPECT_TRUE(std::is_sorted(m.begin(), m.end()));
  }
}

}  // namespace
}  // namespace trailscope::metrics
