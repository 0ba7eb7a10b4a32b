#pragma once
// Endpoint mean-shift clustering (CUBu, IEEE TVCG 2016; the original code's bundleEndpointsGPU). Private to
// compute/.
#include "steps.hpp"

namespace trailscope::bundling::detail {

/// The endpoints of every polyline (2 per polyline: start, end; z = 1) moved `ms_iterations` times up
/// the gradient of their own density (the loop's splat and convolve, kernel ms_h decaying to 2 px; the
/// move is eps·h along the gradient, or the Newton step to the local maximum when that is shorter, so
/// that clusters converge instead of oscillating), so that the ends of nearby nodes gather at common
/// points. Reference (C++) implementation:
/// the endpoint set is small (2 per polyline), and both backends call it, so their results agree.
Points mean_shift_endpoints(const Points& pts, const BundleParams& params,
                            const std::vector<std::uint32_t>& weights, const ProgressFn& progress,
                            const CancelToken* cancel);

/// mean_shift_endpoints, then every polyline becomes [start, clustered start, its interior points,
/// clustered end, end]: the bundle runs from each node to its cluster and on from there.
Points cluster_endpoints(const Points& pts, const BundleParams& params,
                         const std::vector<std::uint32_t>& weights, const ProgressFn& progress,
                         const CancelToken* cancel);

/// After bundling with clustered ends: `lambda_ends` Laplacian smoothing (window int(ms_h / spl) points,
/// one pass) of the points within ms_h px of arc length from either end, so that the terminations
/// ("detail") curve smoothly into the bundles ("core"). The ends themselves stay.
void smooth_ends(Points& pts, const BundleParams& params);

}  // namespace trailscope::bundling::detail
