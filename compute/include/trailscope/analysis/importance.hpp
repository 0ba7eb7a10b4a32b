#pragma once
// Parameter importance: which inputs of a set of runs (tracker parameters) explain an output (a metric),
// the way experiment dashboards show it (W&B: random-forest importance beside linear correlation; Optuna:
// mean decrease in impurity of a random forest). For each input: Pearson's r and Spearman's rho with the
// output, and the forest's normalised mean decrease in impurity (variance), which also catches
// non-monotonic and interacting effects that a correlation misses.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace trailscope::analysis {

struct ForestOptions {
  int trees = 100;                  ///< 1..1000
  int max_depth = 8;                ///< 1..30
  int min_leaf = 3;                 ///< samples per leaf, >= 1
  double max_features = 1.0 / 3.0;  ///< share of the inputs tried at each split, (0, 1]
  std::uint64_t seed = 1;           ///< bootstrap and feature sampling; the same seed gives the same result
};

struct Importance {
  std::string name;
  double pearson = 0;   ///< NaN when the input or the output is constant
  double spearman = 0;  ///< Pearson of the ranks (average ranks for ties); NaN as above
  double forest = 0;    ///< share of the forest's total impurity decrease, in [0, 1]; inputs sum to 1
};

struct ImportanceResult {
  std::vector<Importance> inputs;  ///< in input order
  double forest_r2 = 0;            ///< out-of-bag R^2 of the forest (how much of the output it explains)
  std::size_t samples = 0;
};

/// `x`: samples x inputs, row-major (x[i * names.size() + j]); `y`: one output per sample. Rows with a
/// non-finite output are skipped. Throws Error(invalid_argument, "x") for a size mismatch or non-finite
/// input, Error(unprocessable, "y") for fewer than 4 usable samples, Error(invalid_argument, option name)
/// for options out of range, Error(payload_too_large, "x") beyond limits::kMaxImportanceSamples.
ImportanceResult parameter_importance(const std::vector<double>& x, const std::vector<std::string>& names,
                                      const std::vector<double>& y, const ForestOptions& options = {});

/// Pearson's correlation (NaN when either side is constant or n < 2).
double pearson(const std::vector<double>& a, const std::vector<double>& b);
/// Average ranks (1-based; ties share the mean rank).
std::vector<double> ranks(const std::vector<double>& v);

}  // namespace trailscope::analysis
