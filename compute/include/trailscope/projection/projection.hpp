#pragma once
// Multidimensional projections: N points of D dimensions (projection::Table) to N points in 2D.
//
// Every method follows the dispatch convention of compute/src/ocl/dispatch.hpp: `<method>(…, backend)`
// runs the OpenCL path (the O(N²)/O(N·D) products on the device, small dense solves on the host) or
// the same-named C++ reference `<method>_ref`, falling back to the reference when OpenCL cannot run
// (an error instead under TRAILSCOPE_OPENCL_STRICT=1). The OpenCL paths compute in float on the device
// and accumulate long sums in double on the host; the references compute in double. No device needs
// cl_khr_fp64.
//
// Coordinates are in the units of the (standardised, by default) input: PCA and MDS scores, Force
// Scheme and LAMP positions that approximate the input distances; t-SNE coordinates have no unit.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "trailscope/core/backend.hpp"
#include "trailscope/core/progress.hpp"
#include "trailscope/projection/table.hpp"

namespace trailscope::projection {

enum class Method { pca, mds, tsne, force, lamp };
/// "pca" | "mds" | "tsne" | "force" | "lamp"; throws invalid_argument(param) otherwise.
Method parse_method(std::string_view text, const std::string& param = "method");
const char* to_string(Method m) noexcept;

struct Embedding {
  std::size_t rows = 0;
  std::vector<double> xy;  ///< rows × 2, row-major
  std::string path;        ///< "opencl" or "cpu": which path of the method ran
  std::string variant;     ///< e.g. "exact", "landmark", "barnes-hut"
  std::vector<std::pair<std::string, double>> timings_ms;  ///< phase name → milliseconds
  double x(std::size_t i) const { return xy[2 * i]; }
  double y(std::size_t i) const { return xy[2 * i + 1]; }
};

/// Options of project(); the per-method ones are ignored by the other methods.
struct ProjectOptions {
  Method method = Method::pca;
  bool standardize = true;  ///< z-score the columns first (projection::standardize)
  Backend backend = Backend::auto_;
  std::uint64_t seed = 42;  ///< every random choice (init, landmarks, control points, sampling)
  /// t-SNE: perplexity in [1, limits::kMaxPerplexity], and < (N − 1) / 3 so that the 3·perplexity
  /// nearest neighbours exist.
  double perplexity = 30.0;
  /// Iterations of the main phase: t-SNE (after the exaggeration phase; default 750), Force Scheme
  /// (default 100). 0 = the method's default. At most limits::kMaxProjectionIterations.
  int iterations = 0;
  int exaggeration_iterations = 250;  ///< t-SNE early-exaggeration phase (openTSNE's default)
  double exaggeration = 12.0;         ///< t-SNE early exaggeration, ≥ 1
  double learning_rate = 0.0;         ///< t-SNE; 0 = max(N / 12, 200)
  /// t-SNE Barnes-Hut opening angle in (0, 1]; the exact O(N²) gradient runs instead when N ≤
  /// limits::kMaxExactTsneRows or theta is 0.
  double theta = 0.5;
  ProgressFn progress;  ///< fraction done and phase name
  const CancelToken* cancel = nullptr;
};

/// Validates `table`, standardises a copy when asked, and runs the method. Throws Error(invalid_argument,
/// <option>) for a bad option, Error(payload_too_large, "table") beyond a method's size limit,
/// Error(cancelled) on cancel, Error(backend) under strict mode when OpenCL could not run.
Embedding project(const Table& table, const ProjectOptions& options);

// --- the methods on an already prepared (validated, standardised if wanted) table ------------------

/// PCA: covariance (double) → Eigen's SelfAdjointEigenSolver → the two leading components; each
/// component's sign is chosen so that its largest-magnitude loading is positive (deterministic). Scores
/// of the mean-centred data. With one column the second coordinate is 0.
Embedding pca(const Table& t, Backend backend);
Embedding pca_ref(const Table& t);

/// Classical (Torgerson) MDS of the Euclidean distances: B = −½·J·D²·J, the two leading eigenpairs
/// (λ ≥ 0) by subspace iteration with Rayleigh–Ritz, coordinates v·√λ (sign: largest |entry|
/// positive). Above limits::kMaxExactMdsRows rows: landmark MDS (de Silva & Tenenbaum 2004) on
/// limits::kMdsLandmarks landmarks drawn at random with `seed`.
Embedding mds(const Table& t, std::uint64_t seed, Backend backend);
Embedding mds_ref(const Table& t, std::uint64_t seed);

struct TsneOptions {
  double perplexity = 30.0;
  int iterations = 750;
  int exaggeration_iterations = 250;
  double exaggeration = 12.0;
  double learning_rate = 0.0;
  double theta = 0.5;
  std::uint64_t seed = 42;
  ProgressFn progress;
  const CancelToken* cancel = nullptr;
};
/// t-SNE with openTSNE's defaults: affinities from the k = ⌊3·perplexity⌋ nearest neighbours (brute
/// force), perplexity matched per point by bisection on the Gaussian precision, symmetrised P; PCA
/// initialisation scaled to std 1e-4; early exaggeration for `exaggeration_iterations` with momentum
/// 0.5, then momentum 0.8; delta-bar-delta gains (+0.2 / ×0.8, ≥ 0.01). Gradient without the factor 4
/// (openTSNE's convention, for which the learning rate max(N/12, 200) is meant). Repulsion exact when
/// N ≤ limits::kMaxExactTsneRows or theta == 0, else Barnes-Hut with opening angle theta.
Embedding tsne(const Table& t, const TsneOptions& o, Backend backend);
Embedding tsne_ref(const Table& t, const TsneOptions& o);

/// Force Scheme (Tejada, Minghim, Nonato 2003) in its parallel form: every iteration moves each point
/// by the mean of the forces (δ_ij − d_ij)·(y_i − y_j)/d_ij of all other points, all computed from the
/// same positions. That step is a Guttman transform (SMACOF with unit weights), so the raw stress never
/// increases; Tejada's sequential sweep has no parallel form. Seeded uniform start in [0, max δ]².
/// At most limits::kMaxForceSchemeRows rows (the N² distance matrix is kept).
Embedding force_scheme(const Table& t, int iterations, std::uint64_t seed, Backend backend);
Embedding force_scheme_ref(const Table& t, int iterations, std::uint64_t seed);

/// LAMP (Joia, Coimbra, Cuminato, Paulovich, Nonato 2011): ⌈√N⌉ control points drawn with `seed`, placed
/// by Force Scheme (100 iterations), then every point mapped by the orthogonal affine map that best
/// takes its control points, weighted by 1 / squared distance, to their positions (lamp_map).
Embedding lamp(const Table& t, std::uint64_t seed, Backend backend);
Embedding lamp_ref(const Table& t, std::uint64_t seed);

/// The LAMP map alone, for given control points (row indices of `t`) and their 2D positions
/// (controls.size() × 2). A point at distance 0 from a control point takes its position. Throws
/// invalid_argument("controls") for fewer than 2 controls or an index out of range.
std::vector<double> lamp_map(const Table& t, const std::vector<std::size_t>& controls,
                             const std::vector<double>& control_xy, Backend backend);
/// Reference: per point, AᵀB by Eigen and M = U·Vᵀ from Eigen's JacobiSVD. (The OpenCL kernel uses
/// the equivalent polar factor AᵀB·(BᵀA·AᵀB)^(−1/2) in closed form.)
std::vector<double> lamp_map_ref(const Table& t, const std::vector<std::size_t>& controls,
                                 const std::vector<double>& control_xy);

// --- building blocks, public for the tests ----------------------------------------------------------

/// The k nearest neighbours of every row (Euclidean, itself excluded), ascending by (distance, index):
/// idx and sqdist are rows × k. Brute force; on OpenCL one work-item per row. 1 ≤ k < rows.
struct Knn {
  std::size_t rows = 0;
  int k = 0;
  std::vector<std::int32_t> idx;
  std::vector<float> sqdist;
};
Knn knn(const Table& t, int k, Backend backend);
Knn knn_ref(const Table& t, int k);

/// The symmetric t-SNE affinities in CSR form (sum 1), from the kNN graph with perplexity matched per
/// row (bisection on the precision β of exp(−β·d²) until |H − log(perplexity)| < 1e-5, 200 steps at
/// most).
struct Affinities {
  std::size_t rows = 0;
  std::vector<std::int64_t> row_start;  ///< rows + 1
  std::vector<std::int32_t> col;
  std::vector<double> p;
};
Affinities tsne_affinities(const Knn& knn, double perplexity);

/// One t-SNE gradient (openTSNE convention) at positions `y` (rows × 2): exaggeration·attraction −
/// repulsion / Z. theta 0 = exact repulsion. For the OpenCL-versus-reference tests of one step.
std::vector<double> tsne_gradient(const Affinities& p, const std::vector<double>& y, double exaggeration,
                                  double theta, Backend backend);
std::vector<double> tsne_gradient_ref(const Affinities& p, const std::vector<double>& y, double exaggeration,
                                      double theta);

}  // namespace trailscope::projection
