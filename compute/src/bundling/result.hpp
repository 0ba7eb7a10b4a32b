#pragma once
// What bundle() and bundle_ref() share around the loop: input checks, the loop's inputs, and the
// post-processing that turns the loop's points into a Bundled (original correspondence, t, direction
// separation, displacement, lengths, angles, quality). Private to compute/.
#include <functional>
#include <string>

#include "steps.hpp"
#include "trailscope/bundling/bundle.hpp"

namespace trailscope::bundling::detail {

/// Throws as bundle() documents: invalid_argument (parameters, malformed offsets, frame size ≠ size),
/// Error(unprocessable, `input`) (no polylines, a polyline of fewer than 2 points, a non-finite point),
/// Error(payload_too_large, `input`) (more than limits::kMaxBundleEdges polylines or
/// kMaxBundleInputPoints points).
void check_input(const Polylines& input_px, const Frame& frame, const BundleParams& params);

/// Runs a loop implementation: fn(points, weights, out, times) -> void.
using LoopFn = std::function<void(const Points&, const std::vector<std::uint32_t>&, Points&, LoopTimes&)>;

/// check_input, endpoint clustering (when ms_iterations > 0), `loop`, post-processing; times every phase.
Bundled run_bundle(const Polylines& input_px, const Frame& frame, const BundleParams& params,
                   const ProgressFn& progress, const CancelToken* cancel, const LoopFn& loop);

/// Ink and displacement of what is drawn: relax(r, params.relaxation, params.max_displacement) against
/// `input` (bundle pixels), on the size × size image (quality.cpp).
Quality measure_quality(const Polylines& input, const Bundled& r);

/// Arc length of polyline e of `p` (double, segments summed in order).
double polyline_length(const Polylines& p, std::size_t e);

}  // namespace trailscope::bundling::detail
