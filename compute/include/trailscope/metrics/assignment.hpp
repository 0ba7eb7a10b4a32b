#pragma once
// Optimal bipartite assignment, the building block of every tracking metric: CLEAR and HOTA match
// ground truth to tracker boxes per frame, IDF1 matches whole tracks. TrackEval uses
// scipy.optimize.linear_sum_assignment, which is exact; so is this (shortest augmenting paths with
// potentials, the Hungarian method in its Jonker-Volgenant form, O(r^2 c) for r <= c).
#include <span>
#include <utility>
#include <vector>

namespace trailscope::metrics {

/// Minimum-cost assignment of a dense `rows` x `cols` cost matrix (row-major, finite values). Assigns
/// min(rows, cols) pairs, each row and column at most once, so that the summed cost is minimal (the
/// rectangular case of scipy's linear_sum_assignment). Returns, for every row, its column or -1.
/// When several assignments are optimal, which one is returned is unspecified.
/// Throws Error(invalid_argument, "cost") when `cost.size() != rows * cols` or a value is not finite.
std::vector<int> linear_sum_assignment(std::span<const double> cost, int rows, int cols);

/// One candidate pair for max_weight_matching.
struct WeightedPair {
  int row = 0;
  int col = 0;
  double weight = 0;  ///< > 0; pairs not listed weigh 0
};

/// Maximum-weight matching over the listed pairs, absent pairs counting 0: the assignment that
/// linear_sum_assignment(-W) finds for the dense matrix W, restricted to pairs of positive weight (the
/// only ones the metrics keep). The pairs split into connected groups (objects that overlap in a frame,
/// tracks that overlap in time) and each group is solved on its own, which keeps crowded but sparse
/// inputs fast. `pairs` must have distinct (row, col) and positive finite weights; rows < `rows` and
/// cols < `cols`. Returns the matched (row, col) pairs, sorted by row.
std::vector<std::pair<int, int>> max_weight_matching(int rows, int cols, std::span<const WeightedPair> pairs);

}  // namespace trailscope::metrics
