#include "scene.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "rng.hpp"

namespace trailscope::tof::synth {
namespace {
constexpr double kPi = std::numbers::pi;
double deg(double d) {
  return d * kPi / 180.0;
}
double smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3 - 2 * x);
}
Mat3 rot_z(double a) {
  Mat3 m;
  m << std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a), 0, 0, 0, 1;
  return m;
}

// Nominal teat positions (x, y) under the udder, mm: front teats wider apart than rear ones, as on most
// cows (FL, FR, RL, RR).
constexpr double kTeatXY[kTeatCount][2] = {{-62, 52}, {62, 52}, {-42, -50}, {42, -50}};

// Reflectivities (fraction of a white target) at the ToF wavelength (~850 nm): skin reflects well,
// the dark rubber of cups and hoses poorly.
constexpr float kReflTeat = 0.62f, kReflUdder = 0.55f, kReflBelly = 0.45f, kReflLeg = 0.40f,
                kReflTail = 0.35f, kReflCup = 0.25f, kReflHose = 0.20f, kReflWall = 0.80f;

// A motion event: displacement `delta` spread over [t0, t0 + duration) by a smoothstep.
struct Event {
  double t0, duration;
  Vec3 delta;
  int leg;  ///< the hind leg that steps (-1: none)
};

std::vector<Event> draw_events(Rng& rng, double rate_hz, double min_mm, double max_mm, double duration_s,
                               double total_s, bool steps) {
  std::vector<Event> events;
  if (rate_hz <= 0) return events;
  Vec3 drift = Vec3::Zero();
  double t = -std::log(1.0 - rng.uniform()) / rate_hz;
  int leg = 0;
  while (t < total_s) {
    const double angle = rng.uniform(0, 2 * kPi), mag = rng.uniform(min_mm, max_mm);
    // Pull back towards the stall position so that the cow stays near the robot over long videos.
    Vec3 delta(mag * std::cos(angle), mag * std::sin(angle), steps ? 0.0 : rng.uniform(-0.2, 0.2) * mag);
    delta.head<2>() -= 0.6 * drift.head<2>();
    drift += delta;
    events.push_back({t, duration_s, delta, steps ? (leg++ % 2) : -1});
    t += duration_s + -std::log(1.0 - rng.uniform()) / rate_hz;
  }
  return events;
}
}  // namespace

Cow draw_cow(std::uint64_t seed) {
  Rng rng(seed, 0xC0FFEE);
  Cow cow;
  const double scale = rng.uniform(0.9, 1.1);
  cow.udder_semi = Vec3(95, 135, 85) * scale;
  cow.udder_centre = {Vec3(-45 * scale, 0, 0), Vec3(45 * scale, 0, 0)};
  cow.belly_centre = Vec3(0, 250, 380);
  cow.belly_semi = Vec3(320, 800, 330);
  Vec3 centroid = Vec3::Zero();
  for (int k = 0; k < kTeatCount; ++k) {
    Teat& teat = cow.teats[k];
    const double x = kTeatXY[k][0] * scale + rng.uniform(-8, 8),
                 y = kTeatXY[k][1] * scale + rng.uniform(-8, 8);
    // The bottom of the udder half on this side, below (x, y).
    const Vec3& c = cow.udder_centre[x < 0 ? 0 : 1];
    const double qx = (x - c.x()) / cow.udder_semi.x(), qy = (y - c.y()) / cow.udder_semi.y();
    const double z = c.z() - cow.udder_semi.z() * std::sqrt(std::max(0.05, 1 - qx * qx - qy * qy));
    teat.surface = Vec3(x, y, z);
    teat.shape.length_mm = rng.uniform(30, 70);
    teat.shape.diameter_mm = rng.uniform(18, 30);
    teat.shape.tilt_deg = rng.uniform(5, 25);
    teat.r = teat.shape.diameter_mm / 2;
    // Teats point outwards: front ones forward-out, rear ones back-out, give or take 30 deg.
    const double out = std::atan2(k < 2 ? 1.0 : -1.0, x < 0 ? -1.0 : 1.0) + deg(rng.uniform(-30, 30));
    const double tilt = deg(teat.shape.tilt_deg);
    teat.dir = Vec3(std::sin(tilt) * std::cos(out), std::sin(tilt) * std::sin(out), -std::cos(tilt));
    teat.apex = teat.surface + teat.shape.length_mm * teat.dir;
    centroid += teat.apex / kTeatCount;
  }
  cow.tip_centroid = centroid;
  cow.tail_head = Vec3(0, -430, 560);
  cow.tail_length = rng.uniform(850, 950);
  return cow;
}

std::vector<FrameState> plan_motion(const ScenarioParams& p, const Cow& cow, const CupPlan& cups,
                                    Scenario scenario, std::size_t frames, double fps, std::uint64_t seed) {
  Rng rng(seed, 0x5EED);
  const double total = frames / fps + 1.0;
  const MotionParams& m = p.motion;
  const auto steps =
      draw_events(rng, m.step_rate_hz, m.step_min_mm, m.step_max_mm, m.step_duration_s, total, true);
  const auto sudden =
      draw_events(rng, m.sudden_rate_hz, m.sudden_min_mm, m.sudden_max_mm, m.sudden_duration_s, total, false);
  std::array<double, 8> phase;
  for (double& ph : phase) ph = rng.uniform(0, 2 * kPi);
  std::vector<double> swat_times;
  if (p.tail.swats)
    for (double t = rng.uniform(0.5, 2.0); t < total; t += p.tail.swat_interval_s * rng.uniform(0.7, 1.3))
      swat_times.push_back(t);

  std::vector<FrameState> states(frames);
  Vec3 target = Vec3::Zero();
  for (std::size_t f = 0; f < frames; ++f) {
    FrameState& s = states[f];
    const double t = f / fps;
    s.t = t;
    if (scenario == Scenario::plane) {
      s.wall_mm = frames > 1 ? 150.0 + 850.0 * f / (frames - 1) : 150.0;
      continue;
    }
    // Cow: sway + steps + sudden moves; a stepping leg swings its hoof forward and back.
    for (int a = 0; a < 3; ++a)
      s.cow_offset[a] = m.sway_mm[a] * std::sin(2 * kPi * t / m.sway_period_s[a] + phase[a]);
    s.yaw = deg(m.yaw_deg) * std::sin(2 * kPi * t / 9.0 + phase[3]);
    s.leg_offset = {Vec3::Zero(), Vec3::Zero()};
    for (const Event& e : steps) {
      const double u = (t - e.t0) / e.duration;
      s.cow_offset += e.delta * smoothstep(u);
      if (u > 0 && u < 1) {
        const Vec3 dir = Vec3(e.delta.x(), e.delta.y(), 0).normalized();
        s.leg_offset[e.leg] = (120.0 * dir + Vec3(0, 0, 60)) * std::sin(kPi * u);
      }
    }
    for (const Event& e : sudden) s.cow_offset += e.delta * smoothstep((t - e.t0) / e.duration);
    // Tail: idle swinging plus swats.
    s.tail_lateral = deg(p.tail.lateral_deg) * std::sin(2 * kPi * t / p.tail.period_s + phase[4]);
    s.tail_forward =
        deg(p.tail.forward_deg) * (0.5 + 0.5 * std::sin(2 * kPi * t / (1.7 * p.tail.period_s) + phase[5]));
    for (double ts : swat_times) {
      const double u = (t - ts) / p.tail.swat_duration_s;
      if (u > 0 && u < 1) {
        s.tail_forward += deg(p.tail.swat_forward_deg) * std::sin(kPi * u);
        s.tail_lateral += deg(25) * std::sin(2 * kPi * u);
      }
    }
    // Cups: slide on during the slide_frames before the covered interval, off during those after it.
    for (int k = 0; k < kTeatCount; ++k) {
      const FrameInterval& c = cups.covered[k];
      if (c.empty()) continue;
      const double n = static_cast<double>(cups.slide_frames);
      const double fd = static_cast<double>(f);
      if (c.contains(f))
        s.cup[k] = 1;
      else if (fd >= c.begin - n && fd < c.begin)
        s.cup[k] = (fd - (c.begin - n) + 1) / (n + 1);
      else if (fd >= c.end && fd < c.end + n)
        s.cup[k] = 1 - (fd - c.end + 1) / (n + 1);
    }
    // Robot: follows the tip centroid with a first-order lag, at a distance that depends on the profile.
    const Mat3 yaw = rot_z(s.yaw);
    const Vec3 aim = yaw * cow.tip_centroid + s.cow_offset;
    const double alpha = 1.0 - std::exp(-(1.0 / fps) / p.camera.lag_s);
    target = f == 0 ? aim : Vec3(target + alpha * (aim - target));
    const CameraParams& c = p.camera;
    double dist;
    if (c.profile == CameraParams::Profile::cycles) {
      const double u = std::fmod(t, c.cycle_s);
      if (u < c.approach_s)
        dist = c.far_mm + (c.near_mm - c.far_mm) * smoothstep(u / c.approach_s);
      else if (u < c.approach_s + c.hold_s)
        dist = c.near_mm;
      else
        dist = c.near_mm + (c.far_mm - c.near_mm) * smoothstep((u - c.approach_s - c.hold_s) /
                                                               (c.cycle_s - c.approach_s - c.hold_s));
    } else {
      // Cups: approach to 300 mm, hold while the cups go on and come off, back off to 420 mm.
      const double u = frames > 1 ? static_cast<double>(f) / (frames - 1) : 0.0;
      if (u < 0.25)
        dist = 500 - 200 * smoothstep(u / 0.25);
      else if (u < 0.72)
        dist = 300;
      else
        dist = 300 + 120 * smoothstep((u - 0.72) / 0.08);
    }
    const double az =
        deg(c.azimuth_deg + c.azimuth_swing_deg * std::sin(2 * kPi * t / c.azimuth_period_s + phase[6]));
    const double el = deg(c.elevation_deg);
    const Vec3 view(-std::cos(el) * std::sin(az), std::cos(el) * std::cos(az), std::sin(el));
    const Vec3 jitter = c.jitter_mm * Vec3(std::sin(2 * kPi * 7.3 * t), std::sin(2 * kPi * 5.1 * t + 1),
                                           std::sin(2 * kPi * 6.2 * t + 2));
    s.camera = target - dist * view + jitter;
    const Vec3 right = view.cross(Vec3::UnitZ()).normalized(), down = view.cross(right);
    s.world_to_camera.row(0) = right.transpose();
    s.world_to_camera.row(1) = down.transpose();
    s.world_to_camera.row(2) = view.transpose();
  }
  return states;
}

FrameState interpolate(const FrameState& a, const FrameState& b, double w) {
  // The result as a value of the arguments' type: an Eigen expression returned from a lambda would refer
  // to temporaries that are gone by the time it is evaluated.
  const auto mix = [w]<typename T>(const T& x, const T& y) -> T { return x + w * (y - x); };
  FrameState s = a;
  s.t = mix(a.t, b.t);
  s.cow_offset = mix(a.cow_offset, b.cow_offset);
  s.yaw = mix(a.yaw, b.yaw);
  for (int i = 0; i < 2; ++i) s.leg_offset[i] = mix(a.leg_offset[i], b.leg_offset[i]);
  s.tail_lateral = mix(a.tail_lateral, b.tail_lateral);
  s.tail_forward = mix(a.tail_forward, b.tail_forward);
  for (int k = 0; k < kTeatCount; ++k) s.cup[k] = mix(a.cup[k], b.cup[k]);
  s.camera = mix(a.camera, b.camera);
  const Eigen::Quaterniond qa(a.world_to_camera), qb(b.world_to_camera);
  s.world_to_camera = qa.slerp(w, qb).toRotationMatrix();
  s.wall_mm = mix(a.wall_mm, b.wall_mm);
  return s;
}

SceneFrame build_scene(const Cow& cow, const FrameState& s, const ScenarioParams& p, Scenario scenario,
                       const Intrinsics& k) {
  SceneFrame scene;
  auto add = [&](Primitive prim, Object object, float refl, int teat = -1) {
    prim.object = object;
    prim.reflectivity = refl;
    prim.teat = static_cast<std::int8_t>(teat);
    set_screen_rect(prim, k.fx, k.fy, k.cx, k.cy, k.width, k.height);
    if (prim.u1 >= prim.u0 && prim.v1 >= prim.v0) scene.prims.push_back(prim);
  };
  if (scenario == Scenario::plane) {
    add(make_plane(Vec3::UnitZ(), s.wall_mm), Object::wall, kReflWall);
    return scene;
  }
  // cow frame -> camera: x_cam = R (yaw x_cow + offset - camera)
  const Mat3 yaw = rot_z(s.yaw);
  const Mat3 R = s.world_to_camera * yaw;
  const auto P = [&](const Vec3& x) -> Vec3 {
    return s.world_to_camera * (yaw * x + s.cow_offset - s.camera);
  };
  const auto D = [&](const Vec3& v) -> Vec3 { return R * v; };

  add(make_ellipsoid(P(cow.belly_centre), R, cow.belly_semi), Object::body, kReflBelly);
  for (const Vec3& c : cow.udder_centre)
    add(make_ellipsoid(P(c), R, cow.udder_semi), Object::udder, kReflUdder);
  for (int i = 0; i < kTeatCount; ++i) {
    const Teat& t = cow.teats[i];
    // The capsule starts 15 mm inside the udder so that no gap opens where the axis meets the surface.
    add(make_capsule(P(t.surface - 15 * t.dir), P(t.apex - t.r * t.dir), t.r), Object::teat, kReflTeat, i);
    TeatView& v = scene.teats[i];
    v.surface = P(t.surface);
    v.dir = D(t.dir);
    v.apex = P(t.apex);
    v.r = t.r;
    v.cup_on = s.cup[i] >= 1.0;
    if (s.cup[i] > 0) {
      // A cup (liner + shell) 11 mm thicker than the teat, reaching 80 mm below the tip, slid up the axis;
      // its milk hose runs down and back to the robot.
      const Vec3 down = (1.0 - s.cup[i]) * 150.0 * t.dir;
      const Vec3 top = t.surface - 5 * t.dir + down, bottom = t.apex + 80 * t.dir + down;
      add(make_capsule(P(top), P(bottom), t.r + 11), Object::cup, kReflCup, i);
      add(make_capsule(P(bottom), P(bottom + Vec3(0, -120, -260)), 9), Object::hose, kReflHose, i);
    }
  }
  // Hind legs: from the hip down to the hoof, which swings during a step.
  for (int side = 0; side < 2; ++side) {
    const double x = (side == 0 ? -1 : 1) * p.leg_x_mm;
    const Vec3 hip(x, p.leg_y_mm, 450), hoof(x, p.leg_y_mm - 40, -900);
    add(make_capsule(P(hip), P(hoof + s.leg_offset[side]), 62), Object::leg, kReflLeg);
  }
  // Tail: hangs from the tail head, swung sideways and forwards; the switch at its end is thicker.
  const Vec3 dir = Vec3(std::sin(s.tail_lateral), std::sin(s.tail_forward),
                        -std::cos(s.tail_lateral) * std::cos(s.tail_forward))
                       .normalized();
  const Vec3 end = cow.tail_head + cow.tail_length * dir;
  add(make_capsule(P(cow.tail_head), P(cow.tail_head + 0.8 * cow.tail_length * dir), 22), Object::tail,
      kReflTail);
  add(make_capsule(P(cow.tail_head + 0.75 * cow.tail_length * dir), P(end), 40), Object::tail, kReflTail);
  return scene;
}

}  // namespace trailscope::tof::synth
