#pragma once
// Directional bundling (CUBu, IEEE TVCG 2016; the original code's kernelAdvectSitesDirectional): instead of
// climbing the density gradient, each point is pulled toward the points of other polylines near it that run
// the same way and pushed away from those that run the opposite way, so that the two directions of a route
// form two bundles. The reference here and the kernels in compute/kernels/bundle.cl give the same bits: only
// +, −, ×, ÷ and sqrt in double (the angle is a polynomial atan2, not the device's inexact atan2).
// Private to compute/.
#include "steps.hpp"

namespace trailscope::bundling::detail {

/// atan2(y, x) in radians, within 1e−5 of the exact value: a fixed polynomial, so that host and device
/// compute the same bits.
double atan2_poly(double y, double x);
/// Per point, the direction of its polyline there: atan2_poly of p[j+1] − p[j−1] (one-sided at the ends).
std::vector<float> point_directions(const Points& p);
/// Per pixel, 1 + the largest index of the points in it (0: none): one representative point per pixel
/// (the largest index, so that the map does not depend on the order of the atomic writes).
void site_map(const Points& p, int size, std::vector<std::uint32_t>& sites);
/// comp = 1 − (2/π)·|Δangle| in [−1, 1]: +1 parallel, −1 antiparallel.
double direction_compatibility(double a, double b);
/// Moves every point with z > 0 inside the image by step·z·mean|c|·v/|v|, v = Σ (q − p)·c'·(1 − d²/R²)
/// over the site points q of other polylines within radius R (d < R, pixels scanned row by row),
/// c = direction_compatibility, c' = c for c >= 0 and repulsion·c for c < 0. Positions are read before
/// any point moves.
void advect_directional(Points& p, const std::vector<std::uint32_t>& sites, const std::vector<float>& dirs,
                        int size, int radius, double step, double repulsion);

}  // namespace trailscope::bundling::detail
