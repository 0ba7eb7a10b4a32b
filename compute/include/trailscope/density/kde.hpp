#pragma once
// Kernel density smoothing of a line-density aggregate, optional third stage between aggregate and shade.
// A Gaussian kernel of standard deviation radius/3 truncated at `radius` pixels (99.7 % of its mass),
// applied separably (rows, then columns; a Gaussian is the only kernel that is both separable and
// isotropic), weights normalised to sum to 1 per axis so that the total count is preserved away from
// the edges. Pixels outside the canvas count as empty, so smooth a canvas with a margin of `radius`
// pixels and crop it afterwards (aggregate.hpp does): then a tile sees its neighbours' data and tiles
// stay seamless.
//
// Means (altitude, speed) are smoothed as kernel-weighted means: smoothed Σvalue / smoothed count of
// valued segments. Each output pixel is a fixed-order double sum, so the result is deterministic.
#include "trailscope/density/raster.hpp"

namespace trailscope::density {

/// Smooths `a` for `value` with radius `radius_px` (pixels, 0 < radius_px <= 64; fractional radii are
/// allowed: the coarse span estimate uses them). Returns the raster of the whole canvas (margin
/// included), NaN where the smoothed weight is 0. Throws invalid_argument(`kernel_radius`) for a radius
/// out of range.
Raster kde_smooth(const Aggregate& a, DensityValue value, double radius_px);

/// The normalised 1-D Gaussian weights used for `radius_px` (size 2·ceil(radius)+1), for tests.
std::vector<double> kde_weights(double radius_px);

}  // namespace trailscope::density
