#pragma once
// Depth video: what a time-of-flight (ToF) camera delivers per frame (a depth image, an amplitude image,
// a timestamp), the camera's pinhole intrinsics, and optional per-frame ground truth of the four teat
// tips. This header holds the in-memory types only; depth_video_io.hpp reads and writes them.
//
// Units and conventions (the same everywhere in trailscope::tof):
//  - Camera coordinates (OpenCV): x to the image right, y to the image bottom, z along the optical axis,
//    all in millimetres. "Depth" is z, not the radial distance.
//  - Pixel (u, v): column u, row v; the CENTRE of the top-left pixel is (0, 0), so a point projects to
//    u = fx * x / z + cx, v = fy * y / z + cy (px).
//  - In memory, depth is float mm and NaN means "no return" (a hole): a NaN cannot be mistaken for a real
//    distance by arithmetic, whereas 0 would silently pull averages and filters towards the camera. On
//    disk (16-bit PNG) a hole is 0 and depth is rounded to whole millimetres.
//  - Amplitude is float in arbitrary units (the synthetic camera: 1000 = a white wall 1 m away, seen
//    head-on), >= 0. Holes keep the amplitude the sensor measured (often low; it is why they are holes).
//  - Timestamps are seconds from the start of the video.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace trailscope::tof {

/// The four teats, in this order everywhere (arrays of per-teat data, manifest, tracker logs):
/// front-left, front-right, rear-left, rear-right (left/right as the cow stands).
inline constexpr int kTeatCount = 4;
inline constexpr std::array<std::string_view, kTeatCount> kTeatNames = {"FL", "FR", "RL", "RR"};

/// Pinhole intrinsics of the depth camera (no lens distortion: depth cameras deliver rectified images).
struct Intrinsics {
  double fx = 0, fy = 0;      ///< focal lengths, px, > 0
  double cx = 0, cy = 0;      ///< principal point, px (pixel-centre convention, see above)
  int width = 0, height = 0;  ///< image size, px
  /// True when the values were not given by the data but assumed (default_intrinsics); 3D positions
  /// computed from them are then only approximate.
  bool defaulted = false;
};

/// Intrinsics assumed for frames that come without any: 640x480 gets the PrimeSense/Kinect defaults that
/// Open3D uses for its Redwood sample frames (fx = fy = 525, cx = 319.5, cy = 239.5); any other size gets
/// the synthetic ToF camera's field of view (fx = fy = width * 150 / 176, about 60 deg horizontally) with
/// the principal point at the image centre. `defaulted` is set. Throws Error(invalid_argument, "width" or
/// "height") for a size < 1.
Intrinsics default_intrinsics(int width, int height);

/// Axis-aligned box in pixels: top-left corner (x, y) and size (w, h), as in MOTChallenge files. It covers
/// whole pixels: a box of the single pixel (3, 4) is {2.5, 3.5, 1, 1}.
struct BoxPx {
  double x = 0, y = 0, w = 0, h = 0;
  bool operator==(const BoxPx&) const = default;
};

/// Ground truth of one teat in one frame.
struct TeatTruth {
  /// Tip (the lowest point of the rounded end, on the teat axis) in camera coordinates, mm.
  std::array<double, 3> tip_mm{};
  /// The tip projected with the intrinsics, px; empty when the tip is not in front of the camera.
  std::optional<std::array<double, 2>> tip_px;
  /// Whether a tracker can see the tip. The synthetic camera's rule (synth.hpp): the pixel the tip
  /// projects to shows this teat, and at least half (and at least 2) of the pixels that see the tip
  /// region are not covered by anything nearer. Sensor holes and noise do not count.
  bool visible = false;
  /// Bounding box of every pixel whose ray meets the teat, occluded or not (the 2D trackers' target box);
  /// empty when no pixel does.
  std::optional<BoxPx> box_px;
  /// Of the pixels whose ray meets the teat, the share where the teat is the nearest surface, in [0, 1]
  /// (MOTChallenge's "visibility"); 0 when none.
  double visible_fraction = 0;
  /// A teat cup is fully attached (covers the teat).
  bool cup_attached = false;
  bool operator==(const TeatTruth&) const = default;
};

/// Ground truth of one frame: the teats in kTeatNames order.
struct FrameTruth {
  std::array<TeatTruth, kTeatCount> teats{};
  bool operator==(const FrameTruth&) const = default;
};

/// One frame. Images are row-major, width * height values.
struct DepthFrame {
  double timestamp_s = 0;           ///< seconds from the start of the video, non-decreasing over frames
  std::vector<float> depth_mm;      ///< depth z in mm; NaN = no return
  std::vector<float> amplitude;     ///< arbitrary units >= 0; empty when the video has no amplitude
  std::optional<FrameTruth> truth;  ///< ground truth, when known
};

/// What a video is, without its pixels: everything manifest.json says except the per-frame entries.
struct VideoInfo {
  Intrinsics intrinsics;
  std::size_t frame_count = 0;
  double fps = 0;  ///< nominal frame rate, Hz (> 0); the per-frame timestamps are authoritative
  /// Amplitude units per stored 16-bit count: stored = round(amplitude / amplitude_scale), clamped to
  /// 65535, so the quantisation error is at most amplitude_scale / 2.
  double amplitude_scale = 1.0;
  bool has_amplitude = true;
  bool has_truth = false;
  /// True when the source had no timestamps and frame i got i / fps.
  bool timestamps_defaulted = false;
  /// Where the video came from (generator, scenario, seed, or the imported files); free-form JSON object.
  nlohmann::json source = nlohmann::json::object();
};

/// A whole video in memory (frames.size() == info.frame_count).
struct DepthVideo {
  VideoInfo info;
  std::vector<DepthFrame> frames;
};

/// Checks that `frame` fits `info`: image sizes equal width * height (amplitude empty iff the video has
/// none), depth values NaN or finite and > 0, amplitudes finite and >= 0, a finite timestamp, truth
/// present iff info.has_truth. Throws Error(invalid_argument, "frame") naming frame `index` and the fault.
void validate_frame(const VideoInfo& info, const DepthFrame& frame, std::size_t index);

/// Checks intrinsics (finite, fx, fy > 0, size within limits::kMaxVideoPixels), fps > 0, amplitude_scale > 0
/// and frame_count <= limits::kMaxVideoFrames. Throws Error(invalid_argument or payload_too_large) naming
/// the parameter.
void validate_info(const VideoInfo& info);

}  // namespace trailscope::tof
