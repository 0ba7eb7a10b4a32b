// bundle_ref(): the single-threaded C++ reference of the whole bundling (steps.cpp's loop).
#include "bundling/result.hpp"
#include "trailscope/bundling/bundle.hpp"

namespace trailscope::bundling {

Bundled bundle_ref(const Polylines& input_px, const Frame& frame, const BundleParams& params,
                   const ProgressFn& progress, const CancelToken* cancel) {
  Bundled r = detail::run_bundle(input_px, frame, params, progress, cancel,
                                 [&](const detail::Points& in, const std::vector<std::uint32_t>& weights,
                                     detail::Points& out, detail::LoopTimes& times) {
                                   out = detail::run_loop_ref(in, params, weights, times, progress, cancel);
                                 });
  r.path = "cpu";
  return r;
}

}  // namespace trailscope::bundling
