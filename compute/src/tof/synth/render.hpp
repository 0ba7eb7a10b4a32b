#pragma once
// Ray casting of one SceneFrame into depth, amplitude and ground truth (the sensor model of synth.hpp).
// Internal to compute/src/tof/synth.
#include "rng.hpp"
#include "scenario.hpp"
#include "scene.hpp"

namespace trailscope::tof::synth {

/// Depth and amplitude into frame.depth_mm / frame.amplitude; truth into *truth when non-null. `first` and
/// `last` (both or neither) are the scene a quarter of the exposure before and after it, when the two
/// pairs of samples are taken (null: the scene holds still); the truth is `scene`'s. `rng` supplies the
/// sensor noise (unused when noise_free).
void render_frame(const SceneFrame& scene, const SceneFrame* first, const SceneFrame* last,
                  const Intrinsics& k, const ToFSensor& sensor, bool noise_free, Rng& rng, DepthFrame& frame,
                  FrameTruth* truth);

/// Amplitudes clip here (units): 16 bits at the videos' amplitude_scale of 0.5.
inline constexpr double kAmplitudeMax = 32000;

}  // namespace trailscope::tof::synth
