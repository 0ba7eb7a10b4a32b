#pragma once
// Host side of the projections on OpenCL (compute/src/projection/projection_ocl.cpp, kernels
// compute/kernels/projection_*.cl), declared without OpenCL types. The references are the *_ref
// functions of trailscope/projection/*.hpp; float on the device, no fp64. Each function follows the
// dispatch convention of compute/src/ocl/dispatch.hpp: it returns "" when the kernels ran and wrote the
// result, or the reason they cannot run; it may also throw, which dispatch treats as "cannot run".
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "trailscope/core/progress.hpp"
#include "trailscope/projection/projection.hpp"

namespace trailscope::ocl {

/// Squared (or, with `root`, plain) Euclidean distances between the rows of a (na × dims) and b
/// (nb × dims): out[i·nb + j]; out has na·nb entries.
std::string projection_sqdist_ocl(const float* a, std::size_t na, const float* b, std::size_t nb,
                                  std::size_t dims, bool root, float* out);
/// k nearest neighbours of every row of x (n × dims), itself excluded, ascending by (distance, index):
/// idx and sqdist n × k, 1 ≤ k < n. Distance tiles on the device, selection on the host.
std::string projection_knn_ocl(const float* x, std::size_t n, std::size_t dims, int k, std::int32_t* idx,
                               float* sqdist);
/// Σ_r (x_r − mean)ᵀ(x_r − mean) (dims × dims, row-major), partial sums in float per row chunk, summed in
/// double here.
std::string projection_covariance_ocl(const float* x, std::size_t n, std::size_t dims, const double* mean,
                                      double* cov);
/// out (n × 2) = (x − mean)·w with w dims × 2 row-major.
std::string projection_scores_ocl(const float* x, std::size_t n, std::size_t dims, const double* mean,
                                  const double* w, double* out);
/// Exact classical MDS: B on the device, projection::detail::top_eigen with B·V on the device; xy n × 2
/// (unnormalised signs).
std::string projection_mds_exact_ocl(const float* x, std::size_t n, std::size_t dims, std::uint64_t seed,
                                     const CancelToken* cancel, std::vector<double>& xy);
/// The t-SNE optimisation (projection::detail::tsne_optimize) with attraction and repulsion on the
/// device; y holds the initial layout (n × 2) and receives the result. theta 0 = exact repulsion.
std::string projection_tsne_optimize_ocl(const projection::Affinities& p, const projection::TsneOptions& o,
                                         double theta, std::vector<double>& y);
/// One t-SNE gradient (n × 2) at y.
std::string projection_tsne_gradient_ocl(const projection::Affinities& p, const std::vector<double>& y,
                                         double exaggeration, double theta, std::vector<double>& grad);
/// Force Scheme iterations on the device from the start layout y (n × 2, replaced by the result).
std::string projection_force_ocl(const float* x, std::size_t n, std::size_t dims, int iterations,
                                 const CancelToken* cancel, std::vector<double>& y);
/// LAMP map of every row of x given control rows and their positions; out n × 2.
std::string projection_lamp_map_ocl(const float* x, std::size_t n, std::size_t dims,
                                    const std::vector<std::size_t>& controls,
                                    const std::vector<double>& control_xy, std::vector<double>& out);
/// Runs the projection kernels once on a tiny input (part of opencl_warm_up()). Throws
/// Error(Kind::backend).
void projection_warm_up();

}  // namespace trailscope::ocl
