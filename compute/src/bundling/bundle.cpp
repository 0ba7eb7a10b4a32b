// bundle(): the dispatch between the OpenCL loop (bundle_ocl.cpp) and the reference (steps.cpp),
// under the convention of ocl/dispatch.hpp (op name "bundle").
//
// When `auto` picks OpenCL: on a GPU or accelerator always; on a CPU device (PoCL) when the loop has at
// least kAutoCpuMinPoints points after the first resampling and the advection is not directional.
// Measured on the 2-core build machine (AMD EPYC, PoCL 3.1, defaults: 512 px, h = 32, 15 iterations;
// best of 3–10 runs, machine shared with other builds, load average 1.7–2.3 unless said), OpenCL on
// PoCL's CPU device with the CPU forms of the kernels (bundle.cl, top) vs the single-threaded
// reference, wall ms, and per phase resample / splat / convolve / advect / smooth / post:
//   random, 30 edges, 571 pts            13.5 vs 17.4
//   random, 300 edges, 5.6k pts          12.5 vs 16.2
//   US airlines, 2101 edges, 19k pts     16.7 vs 24.3   (3.0 / 1.0 / 3.0 / 1.6 / 1.2 / 3.7 vs
//                                                        5.5 / 1.1 / 6.7 / 6.1 / 1.8 / 3.1)
//   US migrations, 9780 edges, 54k pts   34.1 vs 43.9   (9.7 / 1.8 / 3.5 / 4.5 / 3.7 / 8.8 vs
//                                                        11.9 / 2.0 / 4.8 / 12.1 / 3.6 / 8.8)
//   random, 10k edges, 189k pts           107 vs 154
//   random, 100k edges, 1.9M pts          691 vs 1394–1730 at load 1.1 (192 / 67 / 21 / 118 / 79 / 194
//                                         vs 406 / 75 / 14 / 557 / 107 / 232); 999 vs 1512 at load 2.2
//   random, 1M edges, 19M pts            6110 vs 18645 at load 1 (1831 / 413 / 24 / 988 / 671 / 1851 vs
//                                         6169 / 737 / 15 / 5802 / 2197 / 3667); 12349 vs 31642 at load 3.6
// Before the CPU forms the OpenCL path was slower than the reference up to migrations (airlines 36.2 vs
// 30.8, migrations 75.2 vs 59.3 in the same runs; 100k 1184, 1M 13454 ms): the splat's atomics (locked
// read-modify-writes on PoCL), and an advection and a convolution that PoCL compiles 3–4× slower than
// their ranged forms. On a 2-core Xeon (the GPU machine's CPU, PoCL pinned to 2 cores; before the
// column bands) the ranged advection gains nothing over the one-point form, and the totals are 1M edges
// 16.4 s vs 30.9 s (before: 22.2 s), 100k 1.93 vs 2.76 s, airlines 42 vs 42 ms. The threshold keeps
// tiny jobs, where either takes a few ms and a first kernel build without warm-up would cost more, on
// the reference. Directional advection has no CPU form (fine-grained, atomic site map) and was not
// measured, so `auto` keeps it off PoCL.
#include <cstddef>
#include <cstdint>
#include <exception>

#include "bundling/result.hpp"
#include "ocl/dispatch.hpp"
#include "bundling/bundle_ocl.hpp"
#include "trailscope/bundling/bundle.hpp"
#include "trailscope/ocl_info.hpp"

namespace trailscope::bundling {
namespace {

// Loop points from which `auto` runs on a CPU OpenCL device (see the top).
constexpr std::size_t kAutoCpuMinPoints = 10000;

// Points of the loop after its first resampling.
std::size_t loop_points(const detail::Points& in, const BundleParams& params) {
  std::size_t n = 0;
  for (std::uint32_t c : detail::resample_counts(in, params.spl)) n += c;
  return n;
}

}  // namespace

Bundled bundle(const Polylines& input_px, const Frame& frame, const BundleParams& params, Backend backend,
               const ProgressFn& progress, const CancelToken* cancel) {
  std::string path, device;
  Bundled r = detail::run_bundle(
      input_px, frame, params, progress, cancel,
      [&](const detail::Points& in, const std::vector<std::uint32_t>& weights, detail::Points& out,
          detail::LoopTimes& times) {
        // Errors of the input (too many points) and cancellation are answers, not reasons to fall back:
        // they leave the OpenCL attempt through `pending` and are rethrown after the dispatch.
        std::exception_ptr pending;
        const bool worth =
            backend == Backend::auto_ &&
            (ocl::device_is_gpu() || (!params.directional && loop_points(in, params) >= kAutoCpuMinPoints));
        const ocl::Path p = ocl::dispatch(
            "bundle", backend, worth,
            [&]() -> std::string {
              try {
                detail::LoopTimes t;
                std::string why = ocl::bundle_loop_ocl(in, params, weights, out, t, progress, cancel);
                if (why.empty()) times = t;
                return why;
              } catch (const Error& e) {
                if (e.kind() != Error::Kind::cancelled && e.kind() != Error::Kind::payload_too_large) throw;
                pending = std::current_exception();
                return {};
              }
            },
            [&] { out = detail::run_loop_ref(in, params, weights, times, progress, cancel); });
        if (pending) std::rethrow_exception(pending);
        path = ocl::to_string(p);
        if (p == ocl::Path::opencl) device = opencl_info().device;
      });
  r.path = path;
  r.device = device;
  return r;
}

}  // namespace trailscope::bundling
