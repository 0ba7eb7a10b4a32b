#include "dmd/boundary.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include <opencv2/imgproc.hpp>

namespace trailscope::dmd::detail {

BoundaryParam trace_boundary(const BinaryImage& layer) {
  const int w = layer.width, h = layer.height;
  BoundaryParam b;
  b.contour.assign(static_cast<std::size_t>(w) * h, -1);
  b.arc.assign(static_cast<std::size_t>(w) * h, 0.f);
  // findContours reads the image only (OpenCV >= 3.2) and treats outside the image as 0, which is
  // the convention of the layer's distance transform too. CHAIN_APPROX_NONE keeps every pixel, in
  // order; RETR_LIST because only membership and order matter, not the hierarchy.
  const cv::Mat mat(h, w, CV_8UC1, const_cast<std::uint8_t*>(layer.pixels.data()));
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mat, contours, cv::RETR_LIST, cv::CHAIN_APPROX_NONE);
  b.length.reserve(contours.size());
  for (std::size_t c = 0; c < contours.size(); ++c) {
    const auto& pts = contours[c];
    double s = 0;
    for (std::size_t k = 0; k < pts.size(); ++k) {
      if (k > 0) {
        const int dx = std::abs(pts[k].x - pts[k - 1].x), dy = std::abs(pts[k].y - pts[k - 1].y);
        s += (dx + dy == 2) ? std::sqrt(2.0) : double(dx + dy);
      }
      const std::size_t i = static_cast<std::size_t>(pts[k].y) * w + pts[k].x;
      // A pixel on a 1-px-wide part is traced twice (once per side); its first position stands.
      if (b.contour[i] < 0) {
        b.contour[i] = static_cast<std::int32_t>(c);
        b.arc[i] = static_cast<float>(s);
      }
    }
    if (pts.size() > 1) {
      const int dx = std::abs(pts.front().x - pts.back().x), dy = std::abs(pts.front().y - pts.back().y);
      s += (dx + dy == 2) ? std::sqrt(2.0) : double(dx + dy);
    }
    b.length.push_back(static_cast<float>(s));
  }
  return b;
}

float boundary_distance(const BoundaryParam& b, std::int32_t contour_a, float arc_a, std::int32_t contour_b,
                        float arc_b) {
  if (contour_a < 0 || contour_b < 0) return 0.f;  // not parametrised: no evidence of collapse
  if (contour_a != contour_b) return std::numeric_limits<float>::infinity();
  const float d = std::abs(arc_a - arc_b);
  return std::min(d, b.length[contour_a] - d);
}

}  // namespace trailscope::dmd::detail
