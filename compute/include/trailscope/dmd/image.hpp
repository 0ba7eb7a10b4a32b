#pragma once
// The plain images of the dense medial descriptor (DMD): 8-bit grey, depth in millimetres and binary
// layers. Row-major, no padding, (0, 0) top-left; no OpenCV or OpenImageIO type crosses this header.
#include <cstdint>
#include <vector>

namespace trailscope::dmd {

/// 8-bit grey image. `pixels.size() == width * height`.
struct GreyImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;
  std::uint8_t at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
};

/// Depth image in millimetres (e.g. a ToF or structured-light frame). A NaN, zero or negative value
/// is a hole (no measurement). `mm.size() == width * height`.
struct DepthImage {
  int width = 0;
  int height = 0;
  std::vector<float> mm;
};

/// A binary layer: 1 = inside (foreground), 0 = outside. `pixels.size() == width * height`.
struct BinaryImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;
  std::uint8_t at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
};

/// Maps depth to grey so that near is bright, which makes the objects closest to the camera (teat
/// tips, for a camera looking up at an udder) the top threshold layers of the DMD:
///   hole (NaN, <= 0) or depth > far_mm  -> 0 (black: nothing there);
///   depth <= near_mm                    -> 255;
///   near_mm < depth <= far_mm           -> 255 - round(254 * (depth - near_mm) / (far_mm - near_mm)),
///                                          i.e. 1 .. 254, linear, so 0 stays reserved for "nothing".
/// Throws invalid_argument("near") unless near_mm is finite and > 0, ("far") unless far_mm is finite
/// and > near_mm, ("depth") if `mm.size() != width * height` or a dimension is < 1.
GreyImage depth_to_grey(const DepthImage& depth, double near_mm, double far_mm);

/// The smallest and largest valid depths (mm) of a frame, the default near/far range of the CLI.
/// Throws invalid_argument("depth") when the frame has no valid pixel.
struct DepthRange {
  double near_mm = 0, far_mm = 0;
};
DepthRange valid_depth_range(const DepthImage& depth);

/// Peak signal-to-noise ratio of `b` against `a` in dB, 10 log10(255^2 / MSE); +infinity when the
/// images are equal. Throws invalid_argument("image") when the sizes differ or are empty.
double psnr(const GreyImage& a, const GreyImage& b);

}  // namespace trailscope::dmd
