#pragma once
// Host side of the CUBu loop on OpenCL (compute/src/bundling/bundle_ocl.cpp, kernels
// compute/kernels/bundle.cl), declared without OpenCL types so that bundle.cpp and the step-by-step
// tests can call it. The references are the steps of compute/src/bundling/steps.hpp. Each function
// follows the dispatch convention of compute/src/ocl/dispatch.hpp: it returns "" when the kernels ran
// and wrote the result, or the reason they cannot run (no OpenCL, no cl_khr_fp64, a buffer over the
// device's limit); it may also throw, which dispatch treats as "cannot run".
#include <cstdint>
#include <string>
#include <vector>

#include "steps.hpp"  // relative: the step-by-step tests include this header by its path
#include "trailscope/bundling/params.hpp"
#include "trailscope/core/progress.hpp"

namespace trailscope::ocl {

/// The whole loop (detail::run_loop_ref) with the points kept on the device. Error(cancelled) and
/// Error(payload_too_large) propagate as from the reference.
std::string bundle_loop_ocl(const bundling::detail::Points& in, const bundling::BundleParams& params,
                            const std::vector<std::uint32_t>& weights, bundling::detail::Points& out,
                            bundling::detail::LoopTimes& times, const ProgressFn& progress,
                            const CancelToken* cancel);
/// The fixed-kernel loop of streaming bundling (detail::run_fixed_ref) on `p` in place: the points are
/// uploaded, `a.iterations` iterations run on the device, and the points are read back.
std::string bundle_fixed_ocl(bundling::detail::Points& p, const std::vector<std::uint32_t>& weights,
                             const bundling::detail::FixedArgs& a, bundling::detail::LoopTimes& times);
/// Runs the bundling kernels once on a tiny input (part of opencl_warm_up()); does nothing on a device
/// without cl_khr_fp64, where bundling never runs on OpenCL. Throws Error(Kind::backend).
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

}  // namespace trailscope::ocl
