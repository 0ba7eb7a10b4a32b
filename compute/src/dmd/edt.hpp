#pragma once
// Exact Euclidean distance transforms on a pixel grid, by the separable lower-envelope-of-parabolas
// method (Felzenszwalb & Huttenlocher, "Distance Transforms of Sampled Functions", 2012): one pass
// down the columns, one along the rows, linear in the pixels. Used forwards (distance and feature
// transform of a layer's outside) and backwards (the union of the disks of a medial axis).
#include <cstdint>
#include <limits>
#include <vector>

namespace trailscope::dmd::detail {

/// "No site at all" as a squared distance.
inline constexpr std::int32_t kNoSite = std::numeric_limits<std::int32_t>::max();

/// Squared distance from every pixel to the nearest site (`site[i] != 0`) of a w x h grid, and with
/// `nearest` non-null the index of one nearest site (the feature transform; -1 without sites).
/// Grids up to 32767 px a side (squared distances then fit in 31 bits).
void distance_transform(const std::uint8_t* site, int w, int h, std::vector<std::int32_t>& squared,
                        std::vector<std::int32_t>* nearest);

/// covered[i] = 1 iff some centre c with radius2[c] > 0 has |i - c|^2 < radius2[c], else 0: the union
/// of open disks, as max_c (radius2[c] - |i - c|^2) > 0 computed separably (a reverse distance
/// transform), so the cost does not grow with the disks' areas.
void union_of_disks(const std::int32_t* radius2, int w, int h, std::vector<std::uint8_t>& covered);

}  // namespace trailscope::dmd::detail
