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

/// Runs every op's kernel variants once on a tiny input, for opencl_warm_up(): that builds the programs
/// and also makes PoCL compile the kernels for the work-group size the ops use (its first enqueue of a
/// kernel costs another 0.1–0.15 s otherwise). Throws Error(Kind::backend) on any failure.
void warm_up_ops();

}  // namespace trailscope::ocl
