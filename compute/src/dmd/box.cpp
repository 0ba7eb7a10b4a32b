#include "dmd/box.hpp"

#include <algorithm>

namespace trailscope::dmd::detail {

Box Box::grown(int m, int w, int h) const {
  if (empty()) return *this;
  return Box{std::max(0, x0 - m), std::max(0, y0 - m), std::min(w - 1, x1 + m), std::min(h - 1, y1 + m)};
}

std::vector<Box> suffix_boxes(const std::vector<std::uint8_t>& index, int w, int h, int levels) {
  std::vector<Box> box(levels, Box{w, h, -1, -1});
  for (int y = 0; y < h; ++y) {
    const std::uint8_t* row = &index[static_cast<std::size_t>(y) * w];
    for (int x = 0; x < w; ++x) {
      Box& b = box[row[x]];
      b.x0 = std::min(b.x0, x);
      b.x1 = std::max(b.x1, x);
      b.y0 = std::min(b.y0, y);
      b.y1 = std::max(b.y1, y);
    }
  }
  for (int i = levels - 2; i >= 0; --i) {  // {index >= i} = {index == i} u {index >= i + 1}
    const Box& up = box[i + 1];
    if (up.empty()) continue;
    Box& b = box[i];
    b = Box{std::min(b.x0, up.x0), std::min(b.y0, up.y0), std::max(b.x1, up.x1), std::max(b.y1, up.y1)};
  }
  return box;
}

}  // namespace trailscope::dmd::detail
