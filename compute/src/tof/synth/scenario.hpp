#pragma once
// The numbers behind each synthetic scenario (synth.hpp), in one place. Internal.
#include <array>
#include <cstddef>

#include "trailscope/tof/synth.hpp"

namespace trailscope::tof::synth {

struct MotionParams {
  std::array<double, 3> sway_mm{15, 10, 4};  ///< slow sway amplitude per world axis
  std::array<double, 3> sway_period_s{5.0, 7.0, 3.5};
  double yaw_deg = 2.0;       ///< slow turning of the body about the vertical
  double step_rate_hz = 0.2;  ///< steps per second (Poisson)
  double step_min_mm = 20, step_max_mm = 60, step_duration_s = 0.3;
  double sudden_rate_hz = 0.03;  ///< sudden moves per second (Poisson)
  double sudden_min_mm = 80, sudden_max_mm = 150, sudden_duration_s = 0.12;
};

struct CameraParams {
  enum class Profile { cycles, cups } profile = Profile::cycles;
  double far_mm = 500, near_mm = 150;              ///< distance from the teat-tip centroid
  double cycle_s = 8, approach_s = 4, hold_s = 1;  ///< cycles: approach, hold near, retreat
  double elevation_deg = 60;                       ///< of the viewing direction above horizontal
  double azimuth_deg = 0;                          ///< 0 = from straight behind the cow, + = from its right
  double azimuth_swing_deg = 12, azimuth_period_s = 11;
  double lag_s = 0.35;     ///< first-order lag of the robot following the udder
  double jitter_mm = 1.5;  ///< arm vibration
};

struct TailParams {
  double lateral_deg = 8, forward_deg = 4, period_s = 2.7;  ///< idle swinging
  bool swats = false;  ///< now and then a swat forward through the camera's view
  double swat_interval_s = 4.0, swat_duration_s = 1.0, swat_forward_deg = 24;
};

struct ScenarioParams {
  MotionParams motion;
  CameraParams camera;
  TailParams tail;
  ToFSensor sensor;                        ///< scenario_sensor (synth.hpp)
  double leg_x_mm = 200, leg_y_mm = -170;  ///< hind legs at (+-x, y) in the cow frame
  enum class Cups { none, one, all } cups = Cups::none;
};

ScenarioParams scenario_params(Scenario s);

/// Cup plan of a scenario for a video of `frames` frames at `fps`: the interval each cup is fully on,
/// and the frames a slide on or off takes.
struct CupPlan {
  std::array<FrameInterval, kTeatCount> covered{};
  std::size_t slide_frames = 1;
};
CupPlan plan_cups(const ScenarioParams& p, std::size_t frames, double fps, std::uint64_t seed);

}  // namespace trailscope::tof::synth
