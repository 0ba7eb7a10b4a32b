#include "scenario.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "rng.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::tof {

std::string_view to_string(Scenario s) {
  switch (s) {
    case Scenario::standard:
      return "standard";
    case Scenario::noisy:
      return "noisy";
    case Scenario::occluded:
      return "occluded";
    case Scenario::cups_attached:
      return "cups-attached";
    case Scenario::fast_motion:
      return "fast-motion";
    case Scenario::plane:
      return "plane";
  }
  return "standard";
}

std::vector<std::string_view> scenario_names() {
  return {"standard", "noisy", "occluded", "cups-attached", "fast-motion", "plane"};
}

Scenario parse_scenario(std::string_view name) {
  for (Scenario s : {Scenario::standard, Scenario::noisy, Scenario::occluded, Scenario::cups_attached,
                     Scenario::fast_motion, Scenario::plane})
    if (to_string(s) == name) return s;
  std::string names;
  for (auto n : scenario_names()) names += (names.empty() ? "" : ", ") + std::string(n);
  throw invalid_argument("scenario",
                         "scenario must be one of " + names + ", not '" + std::string(name) + "'");
}

ToFSensor scenario_sensor(Scenario s) {
  return synth::scenario_params(s).sensor;
}

namespace synth {

ScenarioParams scenario_params(Scenario s) {
  ScenarioParams p;
  switch (s) {
    case Scenario::standard:
    case Scenario::plane:
      break;
    case Scenario::noisy:
      // The realistic worst case of the same camera (synth.hpp, scenario_sensor): sunlight through the
      // barn door puts 600 times the indoor ambient into every sample (the 850 nm band-pass filter lets
      // through what the sun emits in its band); a soiled, wet lens window passes a third of the light,
      // scatters some pixels away (3 % dropouts) and makes the camera's own confidence filter stricter;
      // the camera answers the weak return by integrating four times longer, so motion smears more.
      p.sensor.a0 = 350;
      p.sensor.ambient_e = 1.2e6;
      p.sensor.dropout = 0.03;
      p.sensor.min_amplitude = 40;
      p.sensor.grazing_cos = 0.2;
      p.sensor.exposure_s = 0.004;
      break;
    case Scenario::occluded:
      // The arm comes in from the cow's right, so the right hind leg stands in the line of sight as the
      // cow sways; the tail swats through the view; one cup sits on a teat for a while.
      p.camera.azimuth_deg = 38;
      p.camera.azimuth_swing_deg = 8;
      p.leg_x_mm = 165;
      p.leg_y_mm = -110;
      p.tail.swats = true;
      p.cups = ScenarioParams::Cups::one;
      break;
    case Scenario::cups_attached:
      p.camera.profile = CameraParams::Profile::cups;
      p.motion.step_rate_hz = 0.1;
      p.motion.sudden_rate_hz = 0;
      p.cups = ScenarioParams::Cups::all;
      break;
    case Scenario::fast_motion:
      p.motion.sway_mm = {30, 20, 8};
      p.motion.sway_period_s = {2.5, 3.5, 1.8};
      p.motion.yaw_deg = 4;
      p.motion.step_rate_hz = 1.0;
      p.motion.step_duration_s = 0.2;
      p.motion.sudden_rate_hz = 0.3;
      p.motion.sudden_min_mm = 100;
      p.motion.sudden_max_mm = 180;
      p.motion.sudden_duration_s = 0.1;
      p.camera.lag_s = 0.5;
      break;
  }
  return p;
}

CupPlan plan_cups(const ScenarioParams& p, std::size_t frames, double fps, std::uint64_t seed) {
  CupPlan plan;
  const auto seconds = [&](double s, std::size_t cap) {
    return std::clamp<std::size_t>(static_cast<std::size_t>(std::lround(s * fps)), 1,
                                   std::max<std::size_t>(cap, 1));
  };
  if (p.cups == ScenarioParams::Cups::all) {
    // Rear teats first, as attachment usually goes; short videos get proportionally quicker robots.
    plan.slide_frames = seconds(0.4, frames / 40);
    const std::size_t stagger = seconds(0.6, frames / 40);
    const std::size_t start = frames * 30 / 100, off = frames * 65 / 100;
    constexpr int order[kTeatCount] = {2, 3, 0, 1};  // RL, RR, FL, FR
    for (int k = 0; k < kTeatCount; ++k)
      plan.covered[order[k]] = {start + k * stagger + plan.slide_frames, off};
  } else if (p.cups == ScenarioParams::Cups::one) {
    plan.slide_frames = seconds(0.4, frames / 40);
    Rng rng(seed, 0xC0);
    const int teat = static_cast<int>(rng.next() % kTeatCount);
    plan.covered[teat] = {frames * 40 / 100 + plan.slide_frames, frames * 60 / 100};
  }
  return plan;
}

}  // namespace synth
}  // namespace trailscope::tof
