#pragma once
// Ray casting of one SceneFrame into depth, amplitude and ground truth (the sensor model of synth.hpp).
// Internal to compute/src/tof/synth.
#include "rng.hpp"
#include "scenario.hpp"
#include "scene.hpp"

namespace trailscope::tof::synth {

/// Depth and amplitude into frame.depth_mm / frame.amplitude; truth into *truth when non-null. `rng`
/// supplies the sensor noise (unused when noise_free).
void render_frame(const SceneFrame& scene, const Intrinsics& k, const SensorParams& sensor, bool noise_free,
                  Rng& rng, DepthFrame& frame, FrameTruth* truth);

}  // namespace trailscope::tof::synth
