// Exact assignment: Hungarian method with row/column potentials and Dijkstra-like augmentation
// (Kuhn-Munkres as formulated by Jonker & Volgenant). Each row is added by one shortest augmenting
// path over reduced costs, so the result is optimal without any epsilon scaling.
#include "trailscope/metrics/assignment.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include "trailscope/core/error.hpp"

namespace trailscope::metrics {
namespace {

/// Core solver for n <= m; a(i, j) is the cost of row i, column j. Returns the column of each row.
template <typename Cost>
std::vector<int> solve_wide(int n, int m, Cost&& a) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // 1-based as in the classic formulation: column 0 is a virtual start node.
  std::vector<double> u(n + 1, 0.0), v(m + 1, 0.0), minv(m + 1);
  std::vector<int> p(m + 1, 0), way(m + 1, 0);
  std::vector<char> used(m + 1);
  for (int i = 1; i <= n; ++i) {
    p[0] = i;
    int j0 = 0;
    std::fill(minv.begin(), minv.end(), kInf);
    std::fill(used.begin(), used.end(), 0);
    do {
      used[j0] = 1;
      const int i0 = p[j0];
      double delta = kInf;
      int j1 = 0;
      for (int j = 1; j <= m; ++j) {
        if (used[j]) continue;
        const double cur = a(i0 - 1, j - 1) - u[i0] - v[j];
        if (cur < minv[j]) minv[j] = cur, way[j] = j0;
        if (minv[j] < delta) delta = minv[j], j1 = j;
      }
      for (int j = 0; j <= m; ++j) {
        if (used[j])
          u[p[j]] += delta, v[j] -= delta;
        else
          minv[j] -= delta;
      }
      j0 = j1;
    } while (p[j0] != 0);
    do {  // flip the augmenting path
      const int j1 = way[j0];
      p[j0] = p[j1];
      j0 = j1;
    } while (j0 != 0);
  }
  std::vector<int> col_of_row(n, -1);
  for (int j = 1; j <= m; ++j)
    if (p[j] != 0) col_of_row[p[j] - 1] = j - 1;
  return col_of_row;
}

/// Disjoint-set forest over rows and columns (columns offset by `rows`).
struct Groups {
  std::vector<int> parent;
  explicit Groups(int n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void join(int a, int b) { parent[find(a)] = find(b); }
};

}  // namespace

std::vector<int> linear_sum_assignment(std::span<const double> cost, int rows, int cols) {
  if (rows < 0 || cols < 0 || cost.size() != static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols))
    throw invalid_argument("cost", "cost matrix size does not match rows x cols");
  for (const double c : cost)
    if (!std::isfinite(c)) throw invalid_argument("cost", "cost matrix holds a value that is not finite");
  if (rows == 0 || cols == 0) return std::vector<int>(rows, -1);
  if (rows <= cols) return solve_wide(rows, cols, [&](int i, int j) { return cost[i * cols + j]; });
  // More rows than columns: solve the transpose, then invert the mapping.
  const auto row_of_col = solve_wide(cols, rows, [&](int i, int j) { return cost[j * cols + i]; });
  std::vector<int> col_of_row(rows, -1);
  for (int c = 0; c < cols; ++c)
    if (row_of_col[c] >= 0) col_of_row[row_of_col[c]] = c;
  return col_of_row;
}

std::vector<std::pair<int, int>> max_weight_matching(int rows, int cols,
                                                     std::span<const WeightedPair> pairs) {
  std::vector<std::pair<int, int>> matched;
  if (pairs.empty()) return matched;
  Groups groups(rows + cols);
  for (const auto& p : pairs) groups.join(p.row, rows + p.col);
  // Bucket the pairs by group, then solve each group densely over its own rows and columns.
  std::vector<int> order(pairs.size());
  std::iota(order.begin(), order.end(), 0);
  std::vector<int> root(pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) root[k] = groups.find(pairs[k].row);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return root[a] < root[b]; });
  std::vector<int> row_local(rows, -1), col_local(cols, -1), row_ids, col_ids;
  std::vector<double> cost;
  for (std::size_t begin = 0; begin < order.size();) {
    std::size_t end = begin;
    while (end < order.size() && root[order[end]] == root[order[begin]]) ++end;
    if (end - begin == 1) {  // the common case: an isolated pair matches itself
      matched.emplace_back(pairs[order[begin]].row, pairs[order[begin]].col);
      begin = end;
      continue;
    }
    row_ids.clear(), col_ids.clear();
    for (std::size_t k = begin; k < end; ++k) {
      const auto& p = pairs[order[k]];
      if (row_local[p.row] < 0) row_local[p.row] = static_cast<int>(row_ids.size()), row_ids.push_back(p.row);
      if (col_local[p.col] < 0) col_local[p.col] = static_cast<int>(col_ids.size()), col_ids.push_back(p.col);
    }
    const int r = static_cast<int>(row_ids.size()), c = static_cast<int>(col_ids.size());
    cost.assign(static_cast<std::size_t>(r) * c, 0.0);
    for (std::size_t k = begin; k < end; ++k) {
      const auto& p = pairs[order[k]];
      cost[static_cast<std::size_t>(row_local[p.row]) * c + col_local[p.col]] = -p.weight;
    }
    const auto assigned = linear_sum_assignment(cost, r, c);
    for (int i = 0; i < r; ++i) {
      const int j = assigned[i];
      // Zero-weight pairs fill up the square-ish assignment but are no match.
      if (j >= 0 && cost[static_cast<std::size_t>(i) * c + j] < 0)
        matched.emplace_back(row_ids[i], col_ids[j]);
    }
    for (const int id : row_ids) row_local[id] = -1;
    for (const int id : col_ids) col_local[id] = -1;
    begin = end;
  }
  std::sort(matched.begin(), matched.end());
  return matched;
}

}  // namespace trailscope::metrics
