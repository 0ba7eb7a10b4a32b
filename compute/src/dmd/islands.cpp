// Island removal of one layer (medial.hpp): small inside components are cleared, then small outside
// components filled, with OpenCV's connected components (8-connected inside, 4-connected outside).
#include <string>
#include <tuple>
#include <utility>

#include <opencv2/imgproc.hpp>

#include "trailscope/core/error.hpp"
#include "dmd/islands.hpp"
#include "trailscope/dmd/medial.hpp"

namespace trailscope::dmd {
namespace {

// Sets every pixel of a component of `value` pixels with area < min_area to 1 - value; returns the
// number of components and pixels changed. `extra` is added to the area of pixel 0's component.
std::pair<int, std::int64_t> flip_small(BinaryImage& layer, std::uint8_t value, int connectivity,
                                        std::int64_t min_area, std::int64_t extra) {
  cv::Mat mask(layer.height, layer.width, CV_8UC1);
  for (std::size_t i = 0; i < layer.pixels.size(); ++i) mask.data[i] = layer.pixels[i] == value ? 1 : 0;
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids, connectivity, CV_32S);
  std::vector<std::uint8_t> small(n, 0);
  int count = 0;
  const int first = labels.ptr<int>(0)[0];
  for (int c = 1; c < n; ++c)  // label 0 is the other value
    if (stats.at<int>(c, cv::CC_STAT_AREA) + (c == first ? extra : 0) < min_area) {
      small[c] = 1;
      ++count;
    }
  std::int64_t changed = 0;
  if (count == 0) return {0, 0};
  const int* lab = labels.ptr<int>(0);
  for (std::size_t i = 0; i < layer.pixels.size(); ++i)
    if (small[lab[i]]) {
      layer.pixels[i] = static_cast<std::uint8_t>(1 - value);
      ++changed;
    }
  return {count, changed};
}

}  // namespace

namespace detail {
IslandStats remove_islands_in(BinaryImage& layer, std::int64_t min_area, std::int64_t outside_beyond) {
  IslandStats s;
  if (min_area <= 1) return s;  // every component has at least one pixel
  std::tie(s.islands_removed, s.pixels_cleared) = flip_small(layer, 1, 8, min_area, 0);
  std::tie(s.holes_filled, s.pixels_filled) = flip_small(layer, 0, 4, min_area, outside_beyond);
  return s;
}
}  // namespace detail

IslandStats remove_islands(BinaryImage& layer, std::int64_t min_area) {
  if (layer.width < 1 || layer.height < 1 ||
      layer.pixels.size() != static_cast<std::size_t>(layer.width) * layer.height)
    throw invalid_argument("layer", "layer must be a non-empty binary image with width * height pixels");
  if (min_area < 0)
    throw invalid_argument("min_area", "min_area must be >= 0 (got " + std::to_string(min_area) + ")");
  for (auto& p : layer.pixels) p = p ? 1 : 0;
  return detail::remove_islands_in(layer, min_area, 0);
}

}  // namespace trailscope::dmd
