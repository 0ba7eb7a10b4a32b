#pragma once
// Quality of a projection: how well the 2D layout keeps the neighbourhoods and distances of the data
// (trustworthiness and continuity: Venna & Kaski, ICANN 2001; normalised stress and why it is scaled:
// Smelser, Miller, Kobourov, "'Normalized Stress' is Not Normalized", arXiv 2408.07724, 2024).
// Neighbour ranks are strict: ties in distance are broken by row index, so every metric is
// deterministic.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "trailscope/core/backend.hpp"
#include "trailscope/projection/table.hpp"

namespace trailscope::projection {

struct QualityOptions {
  int k = 10;  ///< neighbourhood size, 1 ≤ k < N/2 (and ≤ limits::kMaxQualityK)
  /// Up to this many rows every metric is exact; above it, `sample` rows drawn with `seed` are the
  /// query points of the neighbourhood metrics (their ranks are still over all N rows) and the pairs
  /// among them feed stress and Shepard. 0 = limits::kMaxQualitySample.
  std::size_t sample = 0;
  std::uint64_t seed = 42;
  Backend backend = Backend::auto_;
};

struct Quality {
  double trustworthiness = 0;            ///< T(k) ∈ [0, 1], 1 = no false neighbours in the layout
  double continuity = 0;                 ///< C(k) ∈ [0, 1], 1 = no lost data neighbours
  double neighborhood_preservation = 0;  ///< mean |N_k ∩ V_k| / k ∈ [0, 1]
  double stress = 0;   ///< Σ(d − α·d̂)² / Σd² with the optimal α = Σd·d̂ / Σd̂², ∈ [0, 1]
  double shepard = 0;  ///< Spearman ρ of (d, d̂) over the pairs, ∈ [−1, 1] (average ranks for ties)
  int k = 0;
  std::size_t queries = 0;  ///< rows whose neighbourhoods were evaluated (N, or the sample)
  bool sampled = false;
  std::string path;  ///< "opencl" or "cpu" (the distance computations)
};

/// Metrics of layout `xy` (rows × 2) for data `t` (the space the method saw: standardise first if it
/// did). Throws invalid_argument("k") / ("xy") for a bad k or a layout of the wrong size.
/// T(k) = 1 − 2/(n·k·(2n − 3k − 1))·Σ_i Σ_{j∈V_k(i)} max(0, r(i,j) − k), C(k) the same with the roles of
/// data and layout swapped; sampled: n·Σ_i becomes (n/queries)·Σ over the queries.
Quality quality(const Table& t, const std::vector<double>& xy, const QualityOptions& o);
Quality quality_ref(const Table& t, const std::vector<double>& xy, const QualityOptions& o);

}  // namespace trailscope::projection
