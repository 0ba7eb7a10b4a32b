// bundle(): the dispatch between the OpenCL loop (ocl/bundle_ocl.cpp) and the reference (steps.cpp),
// under the convention of ocl/dispatch.hpp (op name "bundle").
//
// Why `auto` never picks PoCL's CPU device. Measured on the 2-core build machine (PoCL 3.1, defaults:
// 512 px, h = 32, 15 iterations; best of 6–10 runs, machine shared with other builds), OpenCL vs the
// single-threaded reference: US airlines (2101 edges) 25.6 vs 18.2 ms, US migrations (9780 edges)
// 56.6 vs 43.4 ms. PoCL runs these kernels scalar (its vectoriser gives up on all but the column pass),
// its atomics are locked read-modify-writes, and each of the ~9 commands per iteration costs tens of
// microseconds, so two cores do not make up for it. `auto` therefore considers GPUs and accelerators
// only (as density_lines does); `opencl` still runs on PoCL.
#include <exception>

#include "bundling/result.hpp"
#include "ocl/dispatch.hpp"
#include "ocl/ops.hpp"
#include "trailscope/bundling/bundle.hpp"
#include "trailscope/ocl_info.hpp"

namespace trailscope::bundling {

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
        const bool worth = backend == Backend::auto_ && ocl::device_is_gpu();
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
