#include "trailscope/tof/depth_video.hpp"

#include <cmath>
#include <string>

#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"

namespace trailscope::tof {

Intrinsics default_intrinsics(int width, int height) {
  if (width < 1) throw invalid_argument("width", "width must be >= 1 px, not " + std::to_string(width));
  if (height < 1) throw invalid_argument("height", "height must be >= 1 px, not " + std::to_string(height));
  Intrinsics k;
  k.width = width;
  k.height = height;
  k.defaulted = true;
  if (width == 640 && height == 480) {
    // Open3D's PinholeCameraIntrinsicParameters::PrimeSenseDefault, the camera of its Redwood samples.
    k.fx = k.fy = 525.0;
    k.cx = 319.5;
    k.cy = 239.5;
  } else {
    // The synthetic ToF camera's field of view (synth.hpp: fx = 150 px at 176 px width), scaled.
    k.fx = k.fy = width * 150.0 / 176.0;
    k.cx = (width - 1) / 2.0;
    k.cy = (height - 1) / 2.0;
  }
  return k;
}

void validate_info(const VideoInfo& info) {
  const Intrinsics& k = info.intrinsics;
  if (k.width < 1 || k.height < 1)
    throw invalid_argument("intrinsics", "intrinsics: width and height must be >= 1 px, not " +
                                             std::to_string(k.width) + "x" + std::to_string(k.height));
  const std::size_t pixels = static_cast<std::size_t>(k.width) * static_cast<std::size_t>(k.height);
  if (pixels > limits::kMaxVideoPixels)
    throw Error(Error::Kind::payload_too_large, "intrinsics",
                "intrinsics: " + std::to_string(k.width) + "x" + std::to_string(k.height) +
                    " px exceeds the limit of " + std::to_string(limits::kMaxVideoPixels) +
                    " pixels per frame (kMaxVideoPixels)");
  if (!(std::isfinite(k.fx) && k.fx > 0 && std::isfinite(k.fy) && k.fy > 0))
    throw invalid_argument("intrinsics", "intrinsics: fx and fy must be finite and > 0 px");
  if (!std::isfinite(k.cx) || !std::isfinite(k.cy))
    throw invalid_argument("intrinsics", "intrinsics: cx and cy must be finite");
  if (!(std::isfinite(info.fps) && info.fps > 0))
    throw invalid_argument("fps", "fps must be finite and > 0 Hz");
  if (!(std::isfinite(info.amplitude_scale) && info.amplitude_scale > 0))
    throw invalid_argument("amplitude_scale", "amplitude_scale must be finite and > 0");
  if (info.frame_count > limits::kMaxVideoFrames)
    throw Error(Error::Kind::payload_too_large, "frames",
                "frame_count " + std::to_string(info.frame_count) + " exceeds the limit of " +
                    std::to_string(limits::kMaxVideoFrames) + " frames (kMaxVideoFrames)");
  if (!info.source.is_object()) throw invalid_argument("source", "source must be a JSON object");
}

void validate_frame(const VideoInfo& info, const DepthFrame& frame, std::size_t index) {
  const auto fail = [&](const std::string& what) {
    throw invalid_argument("frame", "frame " + std::to_string(index) + ": " + what);
  };
  const std::size_t pixels =
      static_cast<std::size_t>(info.intrinsics.width) * static_cast<std::size_t>(info.intrinsics.height);
  if (!std::isfinite(frame.timestamp_s)) fail("timestamp_s must be finite");
  if (frame.depth_mm.size() != pixels)
    fail("depth has " + std::to_string(frame.depth_mm.size()) + " values, expected " +
         std::to_string(pixels));
  if (info.has_amplitude && frame.amplitude.size() != pixels)
    fail("amplitude has " + std::to_string(frame.amplitude.size()) + " values, expected " +
         std::to_string(pixels));
  if (!info.has_amplitude && !frame.amplitude.empty())
    fail("amplitude given but the video has none (has_amplitude is false)");
  for (std::size_t i = 0; i < frame.depth_mm.size(); ++i) {
    const float z = frame.depth_mm[i];
    if (!std::isnan(z) && !(std::isfinite(z) && z > 0))
      fail("depth at pixel " + std::to_string(i) + " is " + std::to_string(z) +
           " (must be > 0 mm, or NaN for no return)");
  }
  for (std::size_t i = 0; i < frame.amplitude.size(); ++i) {
    const float a = frame.amplitude[i];
    if (!(std::isfinite(a) && a >= 0))
      fail("amplitude at pixel " + std::to_string(i) + " is " + std::to_string(a) + " (must be >= 0)");
  }
  if (info.has_truth != frame.truth.has_value())
    fail(info.has_truth ? "ground truth missing (the video has truth)"
                        : "ground truth given but the video has none (has_truth is false)");
  if (frame.truth) {
    for (int t = 0; t < kTeatCount; ++t) {
      const TeatTruth& teat = frame.truth->teats[t];
      const std::string name(kTeatNames[t]);
      for (double c : teat.tip_mm)
        if (!std::isfinite(c)) fail("truth of " + name + ": tip_mm must be finite");
      if (!(teat.visible_fraction >= 0 && teat.visible_fraction <= 1))
        fail("truth of " + name + ": visible_fraction must be in [0, 1]");
    }
  }
}

}  // namespace trailscope::tof
