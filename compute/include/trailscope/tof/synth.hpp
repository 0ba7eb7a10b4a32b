#pragma once
// A synthetic time-of-flight camera on an automatic-milking robot arm, with exact ground truth: the test
// bed of the teat tracker (van der Zwan & Telea, VISAPP 2015, evaluated on videos that are not public,
// and no public ToF udder video with ground truth exists).
//
// Camera: 176x144 px by default (the SR4000-class imager of MESA's teat-tracking cameras), any size
// allowed; pinhole, fx = fy = 150 px * width / 176 (about 60 x 51 deg for 176x144), principal point at
// the image centre, 25 fps by default. Modulation 30 MHz (an SR4000 default): the phase of a return
// encodes 2 * range, and mixed returns add as phasors.
//
// Scene (world frame: x to the cow's right, y forward, z up, mm): an udder of two ellipsoid halves under
// the belly (a larger ellipsoid), four teats (capsules: a cylinder with a hemispherical tip) of length
// 30..70 mm from the udder surface, diameter 18..30 mm and tilt 5..25 deg from vertical, drawn from the
// seed; two hind legs (capsules) that lift during steps; a swinging tail (a capsule with a thicker switch);
// teat cups (capsules 11 mm thicker than the teat, with a hose) that slide on, cover the teat, slide off.
// The cow sways slowly (a few cm, a few seconds per period), steps (short fast translations of 2..6 cm in
// 0.3 s) and now and then moves suddenly (8..15 cm in about 0.12 s). The camera looks up and forward at the
// teat tips from below and behind, follows the udder with a 0.35 s lag (the robot's servo loop) and
// approaches from about 500 mm to 150 mm and back, in cycles.
//
// Rendering: one ray per pixel centre, intersected exactly with the analytic surfaces (only the primitives
// whose screen rectangle covers the pixel are tested). Depth is z of the first hit, mm. Amplitude (units:
// 1000 = white wall, 1 m, head-on) = A0 * reflectivity * cos(incidence) / (range / 1 m)^2.
// Sensor effects (off with noise_free):
//  - flying pixels: a pixel at a depth edge (a 4-neighbour misses or differs by > 25 mm) is sampled with
//    2x2 sub-rays whose returns are summed as phasors, giving the mixed depths between foreground and
//    background that real ToF cameras show;
//  - holes (NaN): no surface within 5000 mm, incidence with cos < grazing limit, amplitude below the
//    minimum or at saturation, and random dropouts;
//  - depth noise: Gaussian, sigma = sigma_floor + sigma_gain * sqrt(1000 / amplitude) mm, so it grows with
//    distance (amplitude falls as 1/range^2) and falls with amplitude; amplitude noise sigma = 1 + 1% of it.
//
// Ground truth per frame (computed from the exact geometry, before sensor effects): each teat's tip (the
// apex of its hemispherical end) in camera coordinates, its projection, the box of all pixels whose ray
// meets the teat (below the udder surface), the visible fraction, whether a cup is fully on, and
// VISIBILITY: a tip is visible iff (1) the pixel nearest its projection is in the image and shows that
// teat as the nearest surface, and (2) of the pixels whose ray meets the teat's tip region (surface points
// within one teat radius of the apex), at least half and at least 2 see it unoccluded.
//
// Determinism: frame i depends only on (options, i): the same seed gives the same bytes, in any order and
// on any thread (own xoshiro256** generator and Box-Muller, no std:: distributions).
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string_view>
#include <vector>

#include "trailscope/core/progress.hpp"
#include "trailscope/tof/depth_video.hpp"
#include "trailscope/tof/depth_video_io.hpp"

namespace trailscope::tof {

/// Presets. `plane` is a calibration target, not a cow: a white wall facing the camera whose distance
/// grows linearly from 150 mm (first frame) to 1000 mm (last frame), for measuring the sensor; it has no
/// ground truth.
enum class Scenario {
  standard,       ///< moderate sway, a step every ~5 s, gentle tail, approach cycles of 8 s
  noisy,          ///< standard motion; 3x depth noise, weaker illumination, 3% dropouts
  occluded,       ///< camera from the side (hind leg in the way), tail swats into view, a cup on one teat
  cups_attached,  ///< approach to 300 mm, cups slide onto all four teats one by one, then come off
  fast_motion,    ///< double sway, frequent steps and sudden moves
  plane,          ///< the calibration wall (see above)
};
std::string_view to_string(Scenario s);
/// "standard", "noisy", "occluded", "cups-attached", "fast-motion", "plane". Throws
/// Error(invalid_argument, "scenario") listing the names for anything else.
Scenario parse_scenario(std::string_view name);
std::vector<std::string_view> scenario_names();

/// Default synthetic camera focal length for a 176 px wide image (px).
inline constexpr double kSynthFocal176 = 150.0;

struct SynthOptions {
  Scenario scenario = Scenario::standard;
  std::size_t frames = 250;       ///< 1..limits::kMaxVideoFrames (cups-attached needs >= 20)
  std::uint64_t seed = 1;         ///< cow geometry, motion events and noise all follow from it
  int width = 176, height = 144;  ///< px, 8..1024 each, width * height <= limits::kMaxVideoPixels
  double fps = 25.0;              ///< Hz, 1..1000
  /// Ideal sensor: depth is the exact z of the first surface at the pixel centre, amplitude exact, no
  /// noise, no flying pixels, no holes except where no surface is within range.
  bool noise_free = false;
};

/// Frames [begin, end).
struct FrameInterval {
  std::size_t begin = 0, end = 0;
  bool contains(std::size_t f) const { return f >= begin && f < end; }
  bool empty() const { return end <= begin; }
};

/// The drawn shape of one teat.
struct TeatShape {
  double length_mm = 0;    ///< from the udder surface to the tip, 30..70
  double diameter_mm = 0;  ///< 18..30
  double tilt_deg = 0;     ///< from vertical, 5..25
};

/// The camera. Construction draws the cow and precomputes the motion of every frame (O(frames), small);
/// render() is then a pure function of the frame index, safe to call from several threads at once.
class ToFSynth {
 public:
  /// Throws Error(invalid_argument) naming the option ("frames", "width", "height", "fps") when out of
  /// range, Error(payload_too_large, "frames") beyond limits::kMaxVideoFrames.
  explicit ToFSynth(const SynthOptions& options);
  ~ToFSynth();
  ToFSynth(ToFSynth&&) noexcept;
  ToFSynth& operator=(ToFSynth&&) noexcept;

  const SynthOptions& options() const;
  /// Intrinsics, frame count, fps, amplitude_scale 0.5 (saturation 30000 fits 16 bits), has_truth (all
  /// but `plane`), source = {generator, scenario, seed, noise_free}.
  const VideoInfo& info() const;
  /// Frame `index` (< options().frames, else Error(invalid_argument, "frame")); timestamp index / fps.
  DepthFrame render(std::size_t index) const;
  const std::array<TeatShape, kTeatCount>& teat_shapes() const;
  /// Per teat, the frames during which its cup is fully on (empty when the scenario attaches none).
  /// Sliding on and off takes about 0.4 s before and after each interval.
  const std::array<FrameInterval, kTeatCount>& cup_intervals() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// All frames in memory, rendered in parallel (oneTBB); progress is reported from the calling thread.
DepthVideo synthesize(const SynthOptions& options, const ProgressFn& progress = {});

/// Renders and writes a video straight to disk (folder or pack, atomically; see depth_video_io.hpp) without
/// holding it in memory: frames are rendered in parallel batches and written in order. Returns the
/// synthesiser (for its cup intervals and teat shapes). Throws as ToFSynth and DepthVideoWriter.
ToFSynth write_synthetic_video(const SynthOptions& options, const std::filesystem::path& target,
                               const WriteOptions& write_options, const ProgressFn& progress = {});

}  // namespace trailscope::tof
