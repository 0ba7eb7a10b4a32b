#pragma once
// The medial axis transform of one layer with its salience (medial.hpp), in one place so that the
// pipeline and medial_axis() share it.
#include <cstdint>
#include <vector>

#include "trailscope/dmd/image.hpp"

namespace trailscope::dmd::detail {

/// Image-sized results: `mat_r2` is D on the MAT and 0 elsewhere, `salience` the salience on the MAT
/// (+infinity on loops) and 0 elsewhere.
struct MatWork {
  int w = 0, h = 0;
  std::vector<std::int32_t> mat_r2;
  std::vector<float> salience;
  std::int64_t mat_pixels = 0;
};

/// See medial.hpp for the definitions. Throws invalid_argument("layer") for a malformed layer.
MatWork compute_mat(const BinaryImage& layer);

}  // namespace trailscope::dmd::detail
