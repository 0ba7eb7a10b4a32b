#pragma once
// Arc-length parametrisation of the boundary of a binary layer, the coordinate along which AFMM-style
// importance measures how much boundary collapses onto a skeleton pixel.
#include <cstdint>
#include <vector>

#include "trailscope/dmd/image.hpp"

namespace trailscope::dmd::detail {

struct BoundaryParam {
  /// Per pixel of the layer: the index of the contour it was first traced on, or -1 for pixels that
  /// are not boundary pixels (inside pixels with an outside 4-neighbour or on the image edge).
  std::vector<std::int32_t> contour;
  /// Per pixel: arc length (px, steps of 1 or sqrt 2) from the contour's start to its first visit.
  std::vector<float> arc;
  /// Per contour: total length, closing step included.
  std::vector<float> length;
};

/// Traces every contour (outer and hole borders, 8-connected inside) of `layer`.
BoundaryParam trace_boundary(const BinaryImage& layer);

/// Boundary distance between two parametrised points: the shorter way round a shared contour, or
/// +infinity for points on different contours.
float boundary_distance(const BoundaryParam& b, std::int32_t contour_a, float arc_a, std::int32_t contour_b,
                        float arc_b);

}  // namespace trailscope::dmd::detail
