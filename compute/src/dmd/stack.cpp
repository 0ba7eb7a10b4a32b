// Stacking the reconstructed layers back into a grey image (DMD step 5).
//
// Without interpolation a pixel of band i (covered by layer i, not by i + 1) gets v_i, which shows
// the bands as flat terraces. DMD interpolates between consecutive layers by distance; here a pixel
// x of band i gets
//     lo_i + (hi_i - lo_i) * d_below / (d_below + d_above),
// with d_below the distance from x to the nearest pixel of a lower band, d_above to a higher band
// (5x5 chamfer distances, within about 2 % of Euclidean),
// and lo_i = (v_{i-1} + v_i) / 2, hi_i = (v_i + v_{i+1}) / 2 the values where the quantisation put
// the band's edges. A linear ramp of the input is then reproduced; the band still averages about v_i.
// Where there is no lower band (the canvas) or no higher band anywhere, the band stays flat at v_i,
// so a binary image and the holes of a depth frame come back unchanged.
#include <cmath>

#include <opencv2/imgproc.hpp>
#include <tbb/parallel_for.h>

#include "dmd/box.hpp"
#include "dmd/stages.hpp"

namespace trailscope::dmd::detail {

GreyImage stack_layers(const std::vector<std::uint8_t>& layer_of, int width, int height,
                       const std::vector<int>& levels, bool interpolate) {
  GreyImage out;
  out.width = width;
  out.height = height;
  out.pixels.resize(layer_of.size());
  for (std::size_t i = 0; i < layer_of.size(); ++i)
    out.pixels[i] = static_cast<std::uint8_t>(levels[layer_of[i]]);
  if (!interpolate) return out;

  const int n = static_cast<int>(levels.size());
  // Band i lies in the box of {layer >= i}; grown by one pixel it also holds the nearest lower pixel of
  // every band pixel (beyond the margin nothing is nearer than the margin), and all higher pixels.
  const std::vector<Box> boxes = suffix_boxes(layer_of, width, height, n);
  // Bands write disjoint pixels: they run in parallel.
  tbb::parallel_for(1, n, [&](int band) {
    if (boxes[band].empty() || band + 1 >= n || boxes[band + 1].empty()) return;  // no band above: flat
    const Box box = boxes[band].grown(1, width, height);
    const int bw = box.width(), bh = box.height();
    auto at = [&](int x, int y) {
      return layer_of[static_cast<std::size_t>(y + box.y0) * width + x + box.x0];
    };
    // cv::distanceTransform measures to the nearest zero pixel: zero = site.
    cv::Mat not_below(bh, bw, CV_8UC1), not_above(bh, bw, CV_8UC1), below, above;
    bool any_below = false;
    for (int y = 0; y < bh; ++y)
      for (int x = 0; x < bw; ++x) {
        const std::uint8_t l = at(x, y);
        any_below |= l < band;
        not_below.at<std::uint8_t>(y, x) = l >= band;
        not_above.at<std::uint8_t>(y, x) = l <= band;
      }
    if (!any_below) return;  // no lower band anywhere (the canvas is all covered): flat
    // The 5x5 chamfer distance (within about 2 % of Euclidean) is plenty for a ramp, and several
    // times cheaper than an exact transform.
    cv::distanceTransform(not_below, below, cv::DIST_L2, cv::DIST_MASK_5, CV_32F);
    cv::distanceTransform(not_above, above, cv::DIST_L2, cv::DIST_MASK_5, CV_32F);
    const double lo = 0.5 * (levels[band - 1] + levels[band]);
    const double hi = 0.5 * (levels[band] + levels[band + 1]);
    for (int y = 0; y < bh; ++y)
      for (int x = 0; x < bw; ++x) {
        if (at(x, y) != band) continue;
        const double db = below.at<float>(y, x), da = above.at<float>(y, x);
        out.pixels[static_cast<std::size_t>(y + box.y0) * width + x + box.x0] =
            static_cast<std::uint8_t>(std::lround(lo + (hi - lo) * db / (db + da)));
      }
  });
  return out;
}

}  // namespace trailscope::dmd::detail
