#pragma once
// Stage 1 of the tracker: which pixels to believe. Internal.
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "trailscope/tof/depth_video.hpp"
#include "trailscope/tracker/params.hpp"

namespace trailscope::tracker::detail {

/// The cleaned depth image: NaN where a pixel failed a gate or was a flying pixel, else the median of
/// its valid 3x3 (or 5x5) neighbourhood, mm.
struct PreparedFrame {
  int width = 0, height = 0;
  std::vector<float> z;  ///< row-major, mm, NaN = invalid (and everywhere outside `regions`)
  int valid = 0;
  int flying = 0;
  double flying_threshold_mm = 0;  ///< the threshold used (adapted to the frame's noise)
  double noise_mm = 0;             ///< robust sigma of pixel-to-3x3-median differences, mm
  /// The rectangles prepared this frame, clipped to the image: the whole frame, or the TRACK windows.
  std::vector<cv::Rect> regions;
  /// Per row, the [u0, u1) pixel spans prepared: the union of `regions`, merged.
  std::vector<std::vector<std::pair<int, int>>> spans;
  /// Buffers reused frame to frame (no allocation per frame once warm).
  struct Scratch {
    /// The gated depth with a NaN border of kPad pixels, so that neighbourhoods need no bounds checks;
    /// NaN outside `spans`.
    std::vector<float> gated;
    std::vector<float> med, dev, bucket;
    std::vector<int> count;  ///< valid values in each 3x3 neighbourhood of a row
  } scratch;
  float at(int u, int v) const { return z[static_cast<std::size_t>(v) * width + u]; }
};

/// Amplitude gate (skipped when the frame has no amplitude), depth gate, flying pixels: a pixel whose
/// depth differs from the median of its valid 3x3 neighbourhood by more than max(flying_mm, 5 robust
/// sigmas of the frame's pixel-to-median differences) is a mixed return at a depth edge (ToF cameras
/// average foreground and background there), and a pixel with fewer than 3 valid neighbours is isolated
/// noise. Survivors take the median (median_k 3 or 5; 1 keeps the raw value).
/// `rois`: when given, only pixels inside these rectangles are prepared (the rest stay NaN, and pixels
/// outside them count as invalid neighbours) — in TRACK the tracker looks only at the windows around its
/// predictions.
void prepare_frame(const tof::DepthFrame& frame, int width, int height, const TrackerParams& p,
                   PreparedFrame& out, const std::vector<cv::Rect>* rois = nullptr);

}  // namespace trailscope::tracker::detail
