// ToFSynth: options -> cow, cup plan and per-frame states (once), then one pure render per frame.
#include "trailscope/tof/synth.hpp"

#include <tbb/parallel_for.h>

#include <cmath>
#include <optional>
#include <string>

#include "render.hpp"
#include "rng.hpp"
#include "scenario.hpp"
#include "scene.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"

namespace trailscope::tof {

namespace {
// The ranges ToFSensor documents; the first field out of range is named.
void check_sensor(const ToFSensor& x, double fps) {
  const auto need = [](bool ok, const char* field, const char* range) {
    if (!ok)
      throw invalid_argument(std::string("sensor.") + field,
                             std::string("sensor.") + field + " must be " + range);
  };
  const auto fin = [](double v) { return std::isfinite(v); };
  need(fin(x.a0) && x.a0 > 0, "a0", "> 0");
  need(fin(x.electrons_per_unit) && x.electrons_per_unit > 0, "electrons_per_unit", "> 0");
  need(fin(x.demod_contrast) && x.demod_contrast > 0 && x.demod_contrast <= 1, "demod_contrast", "in (0, 1]");
  need(fin(x.ambient_e) && x.ambient_e >= 0, "ambient_e", ">= 0");
  need(fin(x.read_noise_e) && x.read_noise_e >= 0, "read_noise_e", ">= 0");
  need(fin(x.full_well_e) && x.full_well_e > 0, "full_well_e", "> 0");
  need(fin(x.min_amplitude) && x.min_amplitude >= 0, "min_amplitude", ">= 0");
  need(fin(x.grazing_cos) && x.grazing_cos >= 0 && x.grazing_cos < 1, "grazing_cos", "in [0, 1)");
  need(fin(x.dropout) && x.dropout >= 0 && x.dropout <= 1, "dropout", "in [0, 1]");
  need(fin(x.max_range_mm) && x.max_range_mm > 0, "max_range_mm", "> 0");
  need(fin(x.modulation_hz) && x.modulation_hz > 0, "modulation_hz", "> 0");
  need(fin(x.edge_mm) && x.edge_mm > 0, "edge_mm", "> 0");
  need(fin(x.multipath) && x.multipath >= 0 && x.multipath <= 10, "multipath", "in [0, 10]");
  need(fin(x.exposure_s) && x.exposure_s >= 0 && x.exposure_s <= 1 / fps, "exposure_s", "in [0, 1 / fps]");
}
}  // namespace

struct ToFSynth::Impl {
  SynthOptions options;
  VideoInfo info;
  synth::ScenarioParams params;
  synth::Cow cow;
  synth::CupPlan cups;
  std::vector<synth::FrameState> states;
  std::array<TeatShape, kTeatCount> shapes;
};

ToFSynth::ToFSynth(const SynthOptions& o) : impl_(std::make_unique<Impl>()) {
  if (o.frames < 1) throw invalid_argument("frames", "frames must be >= 1");
  if (o.frames > limits::kMaxVideoFrames)
    throw Error(Error::Kind::payload_too_large, "frames",
                "frames " + std::to_string(o.frames) + " exceeds the limit of " +
                    std::to_string(limits::kMaxVideoFrames) + " frames (kMaxVideoFrames)");
  if (o.scenario == Scenario::cups_attached && o.frames < 20)
    throw invalid_argument("frames", "the cups-attached scenario needs at least 20 frames");
  if (o.width < 8 || o.width > 1024)
    throw invalid_argument("width", "width must be 8..1024 px, not " + std::to_string(o.width));
  if (o.height < 8 || o.height > 1024)
    throw invalid_argument("height", "height must be 8..1024 px, not " + std::to_string(o.height));
  if (static_cast<std::size_t>(o.width) * o.height > limits::kMaxVideoPixels)
    throw Error(Error::Kind::payload_too_large, "width",
                "width * height exceeds the limit of " + std::to_string(limits::kMaxVideoPixels) +
                    " pixels per frame (kMaxVideoPixels)");
  if (!(std::isfinite(o.fps) && o.fps >= 1 && o.fps <= 1000))
    throw invalid_argument("fps", "fps must be 1..1000 Hz");
  Impl& s = *impl_;
  s.options = o;
  Intrinsics& k = s.info.intrinsics;
  k.width = o.width;
  k.height = o.height;
  k.fx = k.fy = kSynthFocal176 * o.width / 176.0;
  k.cx = (o.width - 1) / 2.0;
  k.cy = (o.height - 1) / 2.0;
  s.info.frame_count = o.frames;
  s.info.fps = o.fps;
  // Amplitudes clip at 32000 units (render.cpp): 0.5 units per count keeps them within 16 bits.
  s.info.amplitude_scale = 0.5;
  s.info.has_amplitude = true;
  s.info.has_truth = o.scenario != Scenario::plane;
  s.info.source = {{"generator", "trailscope synth"},
                   {"camera", std::string(kSynthCamera)},
                   {"scenario", std::string(to_string(o.scenario))},
                   {"seed", o.seed},
                   {"noise_free", o.noise_free}};
  s.params = synth::scenario_params(o.scenario);
  if (o.sensor) {
    check_sensor(*o.sensor, o.fps);
    s.params.sensor = *o.sensor;
  }
  s.cow = synth::draw_cow(o.seed);
  s.cups = synth::plan_cups(s.params, o.frames, o.fps, o.seed);
  s.states = synth::plan_motion(s.params, s.cow, s.cups, o.scenario, o.frames, o.fps, o.seed);
  for (int t = 0; t < kTeatCount; ++t) s.shapes[t] = s.cow.teats[t].shape;
}

ToFSynth::~ToFSynth() = default;
ToFSynth::ToFSynth(ToFSynth&&) noexcept = default;
ToFSynth& ToFSynth::operator=(ToFSynth&&) noexcept = default;

const SynthOptions& ToFSynth::options() const {
  return impl_->options;
}
const VideoInfo& ToFSynth::info() const {
  return impl_->info;
}
const std::array<TeatShape, kTeatCount>& ToFSynth::teat_shapes() const {
  return impl_->shapes;
}
const std::array<FrameInterval, kTeatCount>& ToFSynth::cup_intervals() const {
  return impl_->cups.covered;
}

DepthFrame ToFSynth::render(std::size_t index) const {
  const Impl& s = *impl_;
  if (index >= s.options.frames)
    throw invalid_argument("frame", "frame " + std::to_string(index) + " does not exist (the video has " +
                                        std::to_string(s.options.frames) + " frames)");
  const auto scene_of = [&](const synth::FrameState& state) {
    return synth::build_scene(s.cow, state, s.params, s.options.scenario, s.info.intrinsics);
  };
  const synth::SceneFrame scene = scene_of(s.states[index]);
  // The scene when the two pairs of samples are taken (motion artefacts, synth.hpp): a quarter of the
  // exposure towards the previous and the next frame; the first and last frames see no motion beyond
  // themselves.
  std::optional<synth::SceneFrame> first, last;
  const double quarter = 0.25 * s.params.sensor.exposure_s * s.options.fps;  // in frames, <= 0.25
  if (!s.options.noise_free && quarter > 0) {
    first = scene_of(index > 0 ? synth::interpolate(s.states[index], s.states[index - 1], quarter)
                               : s.states[index]);
    last = scene_of(index + 1 < s.states.size()
                        ? synth::interpolate(s.states[index], s.states[index + 1], quarter)
                        : s.states[index]);
  }
  synth::Rng rng(s.options.seed, 0x100000000ull + index);
  DepthFrame frame;
  frame.timestamp_s = static_cast<double>(index) / s.options.fps;
  FrameTruth truth;
  synth::render_frame(scene, first ? &*first : nullptr, last ? &*last : nullptr, s.info.intrinsics,
                      s.params.sensor, s.options.noise_free, rng, frame, s.info.has_truth ? &truth : nullptr);
  if (s.info.has_truth) frame.truth = truth;
  return frame;
}

DepthVideo synthesize(const SynthOptions& options, const ProgressFn& progress) {
  const ToFSynth synth(options);
  DepthVideo video;
  video.info = synth.info();
  video.frames.resize(options.frames);
  constexpr std::size_t kChunk = 64;  // progress granularity; each chunk renders in parallel
  for (std::size_t begin = 0; begin < options.frames; begin += kChunk) {
    const std::size_t end = std::min(options.frames, begin + kChunk);
    tbb::parallel_for(begin, end, [&](std::size_t i) { video.frames[i] = synth.render(i); });
    if (progress) progress(static_cast<double>(end) / options.frames, "render");
  }
  return video;
}

}  // namespace trailscope::tof
