#include "trailscope/analysis/importance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include "core/rng.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"

namespace trailscope::analysis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// splitmix64 (core/rng.hpp): the same seed gives the same forest everywhere.
struct Rng : rng::SplitMix64 {
  using SplitMix64::SplitMix64;
  std::size_t below(std::size_t n) { return static_cast<std::size_t>(next() % n); }
};

struct Data {
  const std::vector<double>& x;
  const std::vector<double>& y;
  std::size_t p;
  double at(std::size_t i, std::size_t j) const { return x[i * p + j]; }
};

// One regression tree grown on `idx` (a bootstrap sample), adding each split's impurity decrease
// (n * variance before - n_left * var_left - n_right * var_right) to `gain` of its input, and returning
// the tree so out-of-bag samples can be predicted.
struct Node {
  int feature = -1;  // -1 = leaf
  double threshold = 0, value = 0;
  int left = -1, right = -1;
};

class TreeBuilder {
 public:
  TreeBuilder(const Data& d, const ForestOptions& o, Rng& rng, std::vector<double>& gain)
      : d_(d), o_(o), rng_(rng), gain_(gain) {}
  std::vector<Node> build(std::vector<std::size_t> idx) {
    nodes_.clear();
    grow(idx, 0, idx.size(), 0);
    return std::move(nodes_);
  }

 private:
  int grow(std::vector<std::size_t>& idx, std::size_t lo, std::size_t hi, int depth) {
    const int id = static_cast<int>(nodes_.size());
    nodes_.push_back({});
    const std::size_t n = hi - lo;
    double sum = 0, sum2 = 0;
    for (std::size_t i = lo; i < hi; ++i) sum += d_.y[idx[i]], sum2 += d_.y[idx[i]] * d_.y[idx[i]];
    nodes_[id].value = sum / n;
    const double sse = sum2 - sum * sum / n;
    if (depth >= o_.max_depth || n < 2 * static_cast<std::size_t>(o_.min_leaf) || sse <= 1e-12) return id;
    // Candidate inputs: a random subset (mtry) without replacement.
    std::vector<std::size_t> feats(d_.p);
    std::iota(feats.begin(), feats.end(), 0);
    const std::size_t mtry =
        std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(o_.max_features * d_.p)));
    for (std::size_t k = 0; k < mtry; ++k) std::swap(feats[k], feats[k + rng_.below(d_.p - k)]);
    double best_gain = 0, best_thr = 0;
    int best_f = -1;
    std::vector<std::pair<double, double>> col(n);
    for (std::size_t k = 0; k < mtry; ++k) {
      const std::size_t f = feats[k];
      for (std::size_t i = 0; i < n; ++i) col[i] = {d_.at(idx[lo + i], f), d_.y[idx[lo + i]]};
      std::sort(col.begin(), col.end());
      double ls = 0, ls2 = 0;
      for (std::size_t i = 0; i + 1 < n; ++i) {
        ls += col[i].second, ls2 += col[i].second * col[i].second;
        const std::size_t nl = i + 1, nr = n - nl;
        if (nl < static_cast<std::size_t>(o_.min_leaf) || nr < static_cast<std::size_t>(o_.min_leaf))
          continue;
        if (col[i].first == col[i + 1].first) continue;  // no threshold between equal values
        const double rs = sum - ls, rs2 = sum2 - ls2;
        const double g = sse - (ls2 - ls * ls / nl) - (rs2 - rs * rs / nr);
        if (g > best_gain)
          best_gain = g, best_thr = 0.5 * (col[i].first + col[i + 1].first), best_f = static_cast<int>(f);
      }
    }
    if (best_f < 0) return id;
    gain_[best_f] += best_gain;
    const auto mid = std::partition(idx.begin() + lo, idx.begin() + hi,
                                    [&](std::size_t s) { return d_.at(s, best_f) <= best_thr; });
    const std::size_t m = static_cast<std::size_t>(mid - idx.begin());
    nodes_[id].feature = best_f;
    nodes_[id].threshold = best_thr;
    const int l = grow(idx, lo, m, depth + 1);
    const int r = grow(idx, m, hi, depth + 1);
    nodes_[id].left = l;
    nodes_[id].right = r;
    return id;
  }

  const Data& d_;
  const ForestOptions& o_;
  Rng& rng_;
  std::vector<double>& gain_;
  std::vector<Node> nodes_;
};

double predict(const std::vector<Node>& t, const Data& d, std::size_t i) {
  int n = 0;
  while (t[n].feature >= 0) n = d.at(i, t[n].feature) <= t[n].threshold ? t[n].left : t[n].right;
  return t[n].value;
}

void check_option(bool ok, const char* name, const std::string& what) {
  if (!ok) throw invalid_argument(name, std::string(name) + " must be " + what);
}

}  // namespace

double pearson(const std::vector<double>& a, const std::vector<double>& b) {
  const std::size_t n = std::min(a.size(), b.size());
  if (n < 2) return kNaN;
  double ma = 0, mb = 0;
  for (std::size_t i = 0; i < n; ++i) ma += a[i], mb += b[i];
  ma /= n, mb /= n;
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < n; ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return saa > 0 && sbb > 0 ? sab / std::sqrt(saa * sbb) : kNaN;
}

std::vector<double> ranks(const std::vector<double>& v) {
  std::vector<std::size_t> order(v.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return v[a] < v[b]; });
  std::vector<double> r(v.size());
  for (std::size_t i = 0; i < order.size();) {
    std::size_t j = i;
    while (j + 1 < order.size() && v[order[j + 1]] == v[order[i]]) ++j;
    const double mean_rank = 0.5 * (i + j) + 1.0;
    for (std::size_t k = i; k <= j; ++k) r[order[k]] = mean_rank;
    i = j + 1;
  }
  return r;
}

ImportanceResult parameter_importance(const std::vector<double>& x_all, const std::vector<std::string>& names,
                                      const std::vector<double>& y_all, const ForestOptions& o) {
  const std::size_t p = names.size();
  if (p == 0 || x_all.size() != y_all.size() * p)
    throw invalid_argument("x", "x must hold " + std::to_string(y_all.size()) + " rows of " +
                                    std::to_string(p) + " inputs, got " + std::to_string(x_all.size()) +
                                    " values");
  check_option(o.trees >= 1 && o.trees <= 1000, "trees", "in [1, 1000]");
  check_option(o.max_depth >= 1 && o.max_depth <= 30, "max_depth", "in [1, 30]");
  check_option(o.min_leaf >= 1, "min_leaf", "at least 1");
  check_option(o.max_features > 0 && o.max_features <= 1, "max_features", "in (0, 1]");
  if (y_all.size() > limits::kMaxImportanceSamples)
    throw Error(Error::Kind::payload_too_large, "x",
                "at most " + std::to_string(limits::kMaxImportanceSamples) + " samples, got " +
                    std::to_string(y_all.size()));
  // Usable rows: finite output (a run without truth has no error to explain).
  std::vector<double> x, y;
  for (std::size_t i = 0; i < y_all.size(); ++i) {
    for (std::size_t j = 0; j < p; ++j)
      if (!std::isfinite(x_all[i * p + j]))
        throw invalid_argument(
            "x", "input '" + names[j] + "' of sample " + std::to_string(i) + " is not a finite number");
    if (!std::isfinite(y_all[i])) continue;
    x.insert(x.end(), x_all.begin() + i * p, x_all.begin() + (i + 1) * p);
    y.push_back(y_all[i]);
  }
  const std::size_t n = y.size();
  if (n < 4)
    throw Error(Error::Kind::unprocessable, "y",
                "importance needs at least 4 samples with a finite output, got " + std::to_string(n));

  ImportanceResult res;
  res.samples = n;
  const std::vector<double> ry = ranks(y);
  for (std::size_t j = 0; j < p; ++j) {
    std::vector<double> col(n);
    for (std::size_t i = 0; i < n; ++i) col[i] = x[i * p + j];
    res.inputs.push_back({names[j], pearson(col, y), pearson(ranks(col), ry), 0.0});
  }
  // The forest: bootstrap samples, out-of-bag predictions for R^2.
  const Data d{x, y, p};
  Rng rng{o.seed};
  std::vector<double> gain(p, 0.0), oob_sum(n, 0.0);
  std::vector<int> oob_count(n, 0);
  for (int t = 0; t < o.trees; ++t) {
    std::vector<std::size_t> idx(n);
    std::vector<char> in_bag(n, 0);
    for (auto& i : idx) i = rng.below(n), in_bag[i] = 1;
    TreeBuilder builder(d, o, rng, gain);
    const auto tree = builder.build(idx);
    for (std::size_t i = 0; i < n; ++i)
      if (!in_bag[i]) oob_sum[i] += predict(tree, d, i), ++oob_count[i];
  }
  const double total = std::accumulate(gain.begin(), gain.end(), 0.0);
  for (std::size_t j = 0; j < p; ++j) res.inputs[j].forest = total > 0 ? gain[j] / total : 0.0;
  double my = std::accumulate(y.begin(), y.end(), 0.0) / n, ss_res = 0, ss_tot = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!oob_count[i]) continue;
    const double e = y[i] - oob_sum[i] / oob_count[i];
    ss_res += e * e;
    ss_tot += (y[i] - my) * (y[i] - my);
  }
  res.forest_r2 = ss_tot > 0 ? 1.0 - ss_res / ss_tot : 0.0;
  return res;
}

}  // namespace trailscope::analysis
