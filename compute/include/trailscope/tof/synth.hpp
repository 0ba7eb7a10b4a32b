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
// 1000 = white wall, 1 m, head-on) = a0 * reflectivity * cos(incidence) / (range / 1 m)^2.
// The sensor (ToFSensor below; off with noise_free) is a continuous-wave lock-in ToF camera as Lange and
// Seitz describe it (IEEE J. Quantum Electronics 37(3), 2001): each pixel takes four correlation samples of
// the returned light at phase offsets 0, 90, 180, 270 deg, one after the other within the exposure, and
// depth follows from the phase of their differences. The error sources are those of the surveys of Foix,
// Alenya and Torras (IEEE Sensors Journal 11(9), 2011) and Hansard, Lee, Choi and Horaud ("Time-of-Flight
// Cameras", Springer 2012), each from its physical cause:
//  - photon shot noise: every sample holds Poisson electrons (signal + ambient light + dark signal) plus
//    read noise, so the range noise is ~ L / (2 sqrt(2) pi) * sqrt(B) / A (L = c / (2 f_mod), B the
//    electrons per sample, A the demodulated amplitude in electrons): it grows as the return weakens
//    (with distance, at grazing incidence, on dark surfaces) and with ambient light;
//  - flying (mixed) pixels: a pixel at a depth edge (a 4-neighbour misses or differs by > edge_mm) is
//    sampled with 2x2 sub-rays whose returns add as phasors, giving the mixed depths between foreground
//    and background that real ToF cameras show;
//  - multipath: light that reaches a surface via another one (single bounce, Lambertian) adds a phasor of
//    the longer path, so concave regions (teat bases against the udder) read too far (Fuchs, ICPR 2010,
//    who computes it from the depth image itself, as done here: the scene's visible surfaces, sampled on
//    a coarse grid, are the secondary sources; occlusion between them is not traced);
//  - motion artefacts: the pixel's two taps integrate in antiphase, so the samples at 0 and 180 deg are
//    taken together, a quarter of the exposure before the frame's timestamp, and those at 90 and 270 deg
//    a quarter after it, each of the scene as it is then; an edge moving across a pixel during the
//    exposure gives a phase that belongs to neither surface (Lindner and Kolb, Dyn3D 2009);
//  - invalid pixels (NaN): no surface within max_range_mm, incidence below the grazing limit, amplitude
//    below the camera's confidence threshold, a saturated sample, and random dropouts.
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
#include <optional>
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
  noisy,          ///< standard motion; the worst-case sensor of scenario_sensor (sunlight, soiled window)
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

/// The camera model's version, in every synthetic video's `source.camera`: it changes whenever the same
/// options render different frames (2: the lock-in sensor of ToFSensor; 1 had Gaussian depth noise and
/// no multipath or motion artefacts).
inline constexpr std::string_view kSynthCamera = "trailscope-tof 2";

/// Default synthetic camera focal length for a 176 px wide image (px).
inline constexpr double kSynthFocal176 = 150.0;

/// The sensor model (see above). Defaults are `standard`'s: an SR4000-class camera (30 MHz, a 5 m
/// unambiguous range) in an indoor barn. Amplitudes are in the units above (1000 = white wall at 1 m).
struct ToFSensor {
  double a0 = 1000;  ///< illumination: amplitude of a white wall at 1 m head-on, > 0
  /// Photo-electrons of demodulated amplitude per amplitude unit, > 0: the light the pixel collects, which
  /// sets the shot noise (on a white wall: about 4.7 mm at 1000 units with the defaults, 1.35 mm at 9000).
  double electrons_per_unit = 40;
  /// Demodulation contrast (amplitude over mean signal per sample), (0, 1]: the rest of the signal is
  /// offset that adds noise but no phase.
  double demod_contrast = 0.5;
  double ambient_e = 2000;      ///< background light and dark signal per sample, electrons, >= 0
  double read_noise_e = 50;     ///< per sample, electrons rms, >= 0
  double full_well_e = 3.6e6;   ///< a sample reaching this saturates and the pixel is invalid, > 0
  double min_amplitude = 25;    ///< confidence threshold: weaker returns are invalid, units, >= 0
  double grazing_cos = 0.12;    ///< invalid below this cos(incidence), [0, 1)
  double dropout = 0.003;       ///< random invalid pixels (dust, dead pixels), probability [0, 1]
  double max_range_mm = 5000;   ///< no return from surfaces beyond, mm, > 0
  double modulation_hz = 30e6;  ///< > 0
  double edge_mm = 25;          ///< depth step that makes a pixel a mixed-pixel candidate, mm, > 0
  double multipath = 1;         ///< scale of the indirect return: 1 physical, 0 none, [0, 10]
  /// Time the four samples span, centred on the frame's timestamp, s, [0, 1 / fps]: 0 freezes the scene.
  double exposure_s = 0.001;
};

/// The sensor of a scenario: `standard`'s defaults for all but `noisy`, the realistic worst case of the
/// same camera: sunlight through the barn door (ambient 1,200,000 e- per sample), a soiled lens window (a
/// third of the light, 3 % dropouts, a higher confidence threshold and grazing limit) and the long
/// integration (4 ms) that a weak return asks for.
ToFSensor scenario_sensor(Scenario s);

struct SynthOptions {
  Scenario scenario = Scenario::standard;
  std::size_t frames = 250;       ///< 1..limits::kMaxVideoFrames (cups-attached needs >= 20)
  std::uint64_t seed = 1;         ///< cow geometry, motion events and noise all follow from it
  int width = 176, height = 144;  ///< px, 8..1024 each, width * height <= limits::kMaxVideoPixels
  double fps = 25.0;              ///< Hz, 1..1000
  /// Ideal sensor: depth is the exact z of the first surface at the pixel centre, amplitude exact, no
  /// noise, no flying pixels, no holes except where no surface is within range.
  bool noise_free = false;
  /// Replaces the scenario's sensor (scenario_sensor) when set; noise_free still wins. Fields are checked
  /// as ToFSensor documents (Error(invalid_argument, "sensor.<field>")).
  std::optional<ToFSensor> sensor;
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
  /// Intrinsics, frame count, fps, amplitude_scale 0.5 (amplitudes clip at 32000 units, which fits 16
  /// bits), has_truth (all but `plane`), source = {generator, camera (kSynthCamera), scenario, seed,
  /// noise_free}.
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
