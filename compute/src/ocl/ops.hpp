#pragma once
// Host sides of the OpenCL ops (compute/src/ocl/<op>_ocl.cpp), declared without OpenCL types so that
// the public ops in compute/src/<area>/ can call them. Each returns "" when the kernel ran and wrote
// its result, or the reason it cannot run; it may also throw (ocl/dispatch.hpp treats that as "cannot
// run").
#include <cstdint>
#include <string>
#include <vector>

#include "trailscope/core/progress.hpp"

namespace trailscope::bundling {
struct BundleParams;
namespace detail {
struct Points;
struct Box;
struct LoopTimes;
struct ResampleArgs;
}  // namespace detail
}  // namespace trailscope::bundling

namespace trailscope::density {
struct LineSegments;
struct Aggregate;
}  // namespace trailscope::density

namespace trailscope::projection {
struct Affinities;
struct TsneOptions;
}  // namespace trailscope::projection

namespace trailscope::ocl {

std::string density_lines_ocl(const density::LineSegments& segments, density::Aggregate& out);

// Bundling (compute/src/ocl/bundle_ocl.cpp, kernels compute/kernels/bundle.cl; the references are in
// compute/src/bundling/steps.hpp). Each needs cl_khr_fp64 and returns why it cannot run otherwise.
/// The whole loop (detail::run_loop_ref) with the points kept on the device. Error(cancelled) and
/// Error(payload_too_large) propagate as from the reference.
std::string bundle_loop_ocl(const bundling::detail::Points& in, const bundling::BundleParams& params,
                            const std::vector<std::uint32_t>& weights, bundling::detail::Points& out,
                            bundling::detail::LoopTimes& times, const ProgressFn& progress,
                            const CancelToken* cancel);
/// Runs the bundling kernels once on a tiny input (part of warm_up_ops). Throws Error(Kind::backend).
void bundle_warm_up();
/// Single steps, for the step-by-step tests against the reference: resample (count, scan, place).
std::string bundle_resample_ocl(const bundling::detail::Points& in, const bundling::detail::ResampleArgs& a,
                                bundling::detail::Points& out);
/// splat + convolve with `radius`: `img` (size², the splat), `box`, and `dens` (size²; only the read
/// region is defined, elsewhere 0).
std::string bundle_density_ocl(const bundling::detail::Points& p, const std::vector<std::uint32_t>& weights,
                               int size, int radius, std::vector<std::uint32_t>& img,
                               bundling::detail::Box& box, std::vector<float>& dens);
/// advect with a given density image (size²).
std::string bundle_advect_ocl(bundling::detail::Points& p, const std::vector<float>& dens, int size,
                              double step);
/// `passes` smoothing passes.
std::string bundle_smooth_ocl(bundling::detail::Points& p, int window, double lambda, int passes);

// Projections (compute/src/ocl/projection_ocl.cpp, kernels compute/kernels/projection_*.cl; the
// references are the *_ref functions of trailscope/projection/*.hpp). Float on the device, no fp64.
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
/// Runs the projection kernels once on a tiny input (part of warm_up_ops). Throws Error(Kind::backend).
void projection_warm_up();

/// Runs every op's kernel variants once on a tiny input, for opencl_warm_up(): that builds the programs
/// and also makes PoCL compile the kernels for the work-group size the ops use (its first enqueue of a
/// kernel costs another 0.1–0.15 s otherwise). Throws Error(Kind::backend) on any failure.
void warm_up_ops();

}  // namespace trailscope::ocl
