#pragma once
// The cow, its motion, the robot's camera path, and the primitives of one frame in camera coordinates.
// Internal to compute/src/tof/synth.
#include <array>
#include <vector>

#include "geometry.hpp"
#include "scenario.hpp"

namespace trailscope::tof::synth {

/// One teat in the cow frame (world axes, udder at rest at the origin), mm.
struct Teat {
  Vec3 surface;  ///< where the axis leaves the udder surface
  Vec3 dir;      ///< unit axis, pointing down towards the tip
  double r = 0;  ///< radius
  Vec3 apex;     ///< the tip: surface + length * dir
  TeatShape shape;
};

struct Cow {
  std::array<Vec3, 2> udder_centre;  ///< left and right halves
  Vec3 udder_semi;
  Vec3 belly_centre, belly_semi;
  std::array<Teat, kTeatCount> teats;
  Vec3 tail_head;
  double tail_length = 0;
  Vec3 tip_centroid;  ///< mean of the four apexes: what the robot aims at
};

/// Draws udder size, teat placement, length, diameter and tilt from the seed.
Cow draw_cow(std::uint64_t seed);

/// Everything that moves, at one frame.
struct FrameState {
  double t = 0;                    ///< s
  Vec3 cow_offset;                 ///< translation of the cow frame in the world, mm
  double yaw = 0;                  ///< rotation of the cow about the vertical through the udder, rad
  std::array<Vec3, 2> leg_offset;  ///< hoof displacement of the left/right hind leg (cow frame)
  double tail_lateral = 0, tail_forward = 0;  ///< rad
  std::array<double, kTeatCount> cup{};       ///< 0 = off, 1 = fully on, between = sliding
  Vec3 camera;                                ///< camera centre in the world
  Mat3 world_to_camera;  ///< rows: camera x (right), y (down), z (optical axis) in the world
  double wall_mm = 0;    ///< plane scenario: wall distance
};

/// The states of all frames: motion events drawn from the seed, then integrated in order (the robot's lag
/// filter needs the previous frame).
std::vector<FrameState> plan_motion(const ScenarioParams& p, const Cow& cow, const CupPlan& cups,
                                    Scenario scenario, std::size_t frames, double fps, std::uint64_t seed);

/// The state a fraction w of the way from a to b (0 gives a, 1 gives b): positions, angles and cups
/// linearly, the camera's orientation by a quaternion slerp. For the instants within one exposure (the
/// motion between two frames is smooth at that scale).
FrameState interpolate(const FrameState& a, const FrameState& b, double w);

/// A teat in camera coordinates.
struct TeatView {
  Vec3 surface, dir, apex;
  double r = 0;
  bool cup_on = false;  ///< fully on (the truth flag)
};

struct SceneFrame {
  std::vector<Primitive> prims;
  std::array<TeatView, kTeatCount> teats;
};

/// The primitives of one frame in camera coordinates, with screen rectangles for `k`.
SceneFrame build_scene(const Cow& cow, const FrameState& s, const ScenarioParams& p, Scenario scenario,
                       const Intrinsics& k);

}  // namespace trailscope::tof::synth
