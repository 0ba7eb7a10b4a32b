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
#include <limits>
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
  std::string variant;     ///< e.g. "exact", "landmark", "barnes-hut", "fft"
  std::vector<std::pair<std::string, double>> timings_ms;  ///< phase name → milliseconds
  /// project() with t-SNE: the perplexity used (effective_perplexity of the requested one); NaN otherwise.
  double perplexity = std::numeric_limits<double>::quiet_NaN();
  double x(std::size_t i) const { return xy[2 * i]; }
  double y(std::size_t i) const { return xy[2 * i + 1]; }
};

/// The perplexity t-SNE runs with on `rows` rows: min(perplexity, (rows − 1) / 3), openTSNE's rule
/// (TSNE.prepare_initial: "perplexity too high for the number of samples", lowered with a warning) so that
/// the ⌊3·perplexity⌋ nearest neighbours exist; scikit-learn instead refuses perplexity ≥ n_samples.
/// A 20-run sweep gets 19/3 ≈ 6.33 for the default 30. Throws invalid_argument("table") below 4 rows,
/// where the cap would fall under 1 ("t-SNE needs at least 4 rows (perplexity ≥ 1 needs 3 neighbours);
/// the table has N").
double effective_perplexity(double perplexity, std::size_t rows);

/// Options of project(); the per-method ones are ignored by the other methods.
struct ProjectOptions {
  Method method = Method::pca;
  bool standardize = true;  ///< z-score the columns first (projection::standardize)
  Backend backend = Backend::auto_;
  std::uint64_t seed = 42;  ///< every random choice (init, landmarks, control points, sampling)
  /// t-SNE: perplexity in [1, limits::kMaxPerplexity]. project() runs with effective_perplexity() (capped
  /// at (N − 1) / 3 for small tables, as openTSNE does) and reports it in Embedding::perplexity.
  double perplexity = 30.0;
  /// Iterations of the main phase: t-SNE (after the exaggeration phase; default 500, see
  /// TsneOptions::iterations), Force Scheme (default 100). 0 = the method's default. At most
  /// limits::kMaxProjectionIterations.
  int iterations = 0;
  int exaggeration_iterations = 250;  ///< t-SNE early-exaggeration phase (openTSNE's default)
  double exaggeration = 12.0;         ///< t-SNE early exaggeration, ≥ 1
  double learning_rate = 0.0;         ///< t-SNE; 0 = max(N / 12, 200)
  /// t-SNE: in [0, 1]; 0 asks for the exact O(N²) gradient. Otherwise t-SNE runs exact up to
  /// limits::kMaxExactTsneRows rows and FFT-interpolated above (TsneRepulsion::automatic).
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

/// How the t-SNE repulsion Σ_j w_ij²·(y_i − y_j) and the normalisation Z = Σ_{i≠j} w_ij are computed
/// (w_ij = 1 / (1 + |y_i − y_j|²)); Embedding::variant reports the one that ran.
enum class TsneRepulsion {
  /// exact when N ≤ limits::kMaxExactTsneRows or theta == 0, else fft. FFT interpolation replaced
  /// Barnes-Hut as the default above that size: at 5,000 points it takes about a fifth of the time
  /// per iteration of Barnes-Hut at θ = 0.5 (~0.8 ms against ~4 ms on two cores with PoCL), and its
  /// error is set by the grid (TsneFftOptions) rather than by θ. Barnes-Hut stays available.
  automatic,
  exact,       ///< "exact": O(N²) per iteration
  barnes_hut,  ///< "barnes-hut": quadtree, opening angle theta; O(N log N)
  fft,         ///< "fft": FIt-SNE interpolation on a grid, O(N + G log G) for G grid nodes
};

/// FFT-accelerated interpolation (FIt-SNE, Linderman et al. 2019, as openTSNE implements it): the
/// bounding square of the embedding is cut into boxes × boxes square boxes, each with nodes_per_box²
/// equispaced interpolation nodes; charges (1, y₁, y₂) are spread to the nodes by Lagrange
/// interpolation, convolved with the kernels w and w² sampled on the node grid (by FFT on a zero-padded
/// grid, so the convolution is linear, not circular), and the potentials interpolated back. Lengths are
/// in embedding units (the kernel has width ~1).
struct TsneFftOptions {
  int nodes_per_box = 3;   ///< interpolation nodes per box and axis p, in [2, 8] (openTSNE: 3)
  double box_width = 1.0;  ///< largest box side while boxes < max_boxes (openTSNE: 1), > 0
  int min_boxes = 8;       ///< at least this many boxes per axis, in [1, 512]
  /// At most this many boxes per axis, in [min_boxes, 512]; 0 = ⌈max(√N, 72) / p⌉ (at least
  /// min_boxes), i.e. no more grid nodes than points (from ~5,000 points on), which keeps the FFT's
  /// O(G log G) on the order of the O(N) interpolation. openTSNE has no cap (boxes of side 1 however large
  /// the embedding): at 5,000 points the cap (24 boxes over a ~50-unit embedding) takes about a third off the
  /// time per iteration for a trustworthiness 0.004 lower (0.961 against 0.965 with 50 boxes on the benchmark
  /// data). In any case boxes·nodes_per_box ≤ 512 (memory of the grids).
  int max_boxes = 0;
};

struct TsneOptions {
  double perplexity = 30.0;
  /// Iterations after the early exaggeration. 500, FIt-SNE's default (750 in all, 250 of them
  /// exaggerated), rather than openTSNE's 750: with the learning rate N/12 the layout has settled by
  /// then (Belkina et al. 2019), and on the benchmark's 5,000 × 50 clusters the last 250 of openTSNE's
  /// iterations move trustworthiness(10) by 0.002 (0.9591 against 0.9608; 20,000 rows: 0.9585
  /// against 0.9599) for a quarter of the run time.
  int iterations = 500;
  int exaggeration_iterations = 250;
  double exaggeration = 12.0;
  double learning_rate = 0.0;
  double theta = 0.5;  ///< Barnes-Hut opening angle in [0, 1]; 0 selects exact under `automatic`
  TsneRepulsion repulsion = TsneRepulsion::automatic;
  TsneFftOptions fft;
  std::uint64_t seed = 42;
  ProgressFn progress;
  const CancelToken* cancel = nullptr;
};
/// t-SNE with openTSNE's defaults (but FIt-SNE's iteration count, see TsneOptions::iterations):
/// affinities from the k = ⌊3·perplexity⌋ exact nearest neighbours,
/// perplexity matched per point by bisection on the Gaussian precision, symmetrised P; PCA
/// initialisation scaled to std 1e-4; early exaggeration for `exaggeration_iterations` with momentum
/// 0.5, then momentum 0.8; delta-bar-delta gains (+0.2 / ×0.8, ≥ 0.01). Gradient without the factor 4
/// (openTSNE's convention, for which the learning rate max(N/12, 200) is meant). Repulsion as chosen by
/// `repulsion` (TsneRepulsion). On the OpenCL path the attraction and the point↔grid interpolation run
/// on the device and the grid convolution (FFT) on the host; the kNN step uses the device only when it
/// is a GPU (on a CPU device Eigen's GEMM is the faster way to the same neighbours).
/// Throws invalid_argument(<option>) for a bad option (perplexity, iterations, exaggeration,
/// learning_rate, theta, fft), payload_too_large beyond limits::kMaxTsneRows, cancelled on cancel.
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
/// idx and sqdist are rows × k. Exact. The reference finds candidates by a float GEMM (Eigen,
/// |x|² + |y|² − 2·x·y) and orders them by their double pairwise distances; the OpenCL path computes
/// distance blocks on the device and selects on the host. 1 ≤ k < rows.
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
/// repulsion / Z. theta 0 = exact repulsion, else Barnes-Hut. For the OpenCL-versus-reference tests.
std::vector<double> tsne_gradient(const Affinities& p, const std::vector<double>& y, double exaggeration,
                                  double theta, Backend backend);
std::vector<double> tsne_gradient_ref(const Affinities& p, const std::vector<double>& y, double exaggeration,
                                      double theta);
/// The same gradient with the FFT-interpolated repulsion (tsne_repulsion_fft). Throws
/// invalid_argument("fft") for bad grid options, invalid_argument("y") for a wrong size.
std::vector<double> tsne_gradient_fft(const Affinities& p, const std::vector<double>& y, double exaggeration,
                                      const TsneFftOptions& fft, Backend backend);
std::vector<double> tsne_gradient_fft_ref(const Affinities& p, const std::vector<double>& y,
                                          double exaggeration, const TsneFftOptions& fft);

/// The repulsion terms of every point at positions `y` (rows × 2), rows × 3 row-major:
/// (Σ_{j≠i} w_ij²·(x_i − x_j), Σ_{j≠i} w_ij²·(y_i − y_j), Σ_{j≠i} w_ij). Exact O(N²) sums in double.
std::vector<double> tsne_repulsion_exact_ref(const std::vector<double>& y);
/// The same terms by FFT interpolation (TsneFftOptions). The reference computes in double (FFT by
/// OpenCV's cv::dft); the OpenCL path spreads and gathers on the device in float and convolves on the
/// host in float. Throws invalid_argument("fft") / ("y").
std::vector<double> tsne_repulsion_fft(const std::vector<double>& y, const TsneFftOptions& fft,
                                       Backend backend);
std::vector<double> tsne_repulsion_fft_ref(const std::vector<double>& y, const TsneFftOptions& fft);

}  // namespace trailscope::projection
