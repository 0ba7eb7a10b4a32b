#pragma once
// Bounding boxes of the nested sets {index >= i} of a per-pixel index image, so that each layer's
// work can stay inside the part of the image where the layer is.
#include <cstdint>
#include <vector>

namespace trailscope::dmd::detail {

/// Inclusive pixel box; empty when x1 < x0.
struct Box {
  int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
  bool empty() const { return x1 < x0; }
  int width() const { return x1 - x0 + 1; }
  int height() const { return y1 - y0 + 1; }
  /// Grown by `m` pixels on each side, clipped to a w x h image.
  Box grown(int m, int w, int h) const;
  /// Whether growing by `m` needs no clipping (the box keeps m pixels to every image edge).
  bool inside_with_margin(int m, int w, int h) const {
    return x0 >= m && y0 >= m && x1 + m < w && y1 + m < h;
  }
};

/// boxes[i] = bounding box of {p : index[p] >= i}, for i = 0 .. levels - 1.
std::vector<Box> suffix_boxes(const std::vector<std::uint8_t>& index, int w, int h, int levels);

}  // namespace trailscope::dmd::detail
