#pragma once
// The grey-level stages of run_dmd() (dmd.cpp): layer selection, stacking and segmentation.
#include <array>
#include <cstdint>
#include <vector>

#include "trailscope/dmd/dmd.hpp"

namespace trailscope::dmd::detail {

/// The selected grey levels, ascending, levels[0] = the image minimum (see select.cpp).
std::vector<int> select_levels(const GreyImage& image, const DmdParams& params);

/// For every grey value, the index of the nearest level (ties go to the lower level); values below
/// levels[0] map to 0.
std::array<std::uint8_t, 256> nearest_level_index(const std::vector<int>& levels);

/// The grey image of a stack: `layer_of[i]` is the highest layer whose reconstruction covers pixel
/// i (0 = canvas only). See stack.cpp for the interpolation.
GreyImage stack_layers(const std::vector<std::uint8_t>& layer_of, int width, int height,
                       const std::vector<int>& levels, bool interpolate);

/// Labels (1-based, every pixel) and segments of the component tree of {layer_of >= i}; mean values
/// are taken from `image`; `min_area` is the island threshold in pixels. See dmd.hpp, Segment.
void segment_layers(const std::vector<std::uint8_t>& layer_of, const GreyImage& image,
                    const std::vector<int>& levels, std::int64_t min_area, std::vector<std::int32_t>& labels,
                    std::vector<Segment>& segments);

}  // namespace trailscope::dmd::detail
