#pragma once
// Island removal on a crop of a layer (the public remove_islands() works on whole layers).
#include <cstdint>

#include "trailscope/dmd/medial.hpp"

namespace trailscope::dmd::detail {

/// remove_islands() on `crop`, a part of a larger layer whose pixels beyond the crop are all outside
/// and connected to the crop's outside pixel (0, 0) (the crop keeps a one-pixel outside margin inside
/// the image); `outside_beyond` is their number, added to that component's area. Requires
/// outside_beyond >= min_area, so that the component is never filled. outside_beyond = 0 is the
/// whole-layer case.
IslandStats remove_islands_in(BinaryImage& crop, std::int64_t min_area, std::int64_t outside_beyond);

}  // namespace trailscope::dmd::detail
