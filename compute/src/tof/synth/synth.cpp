// ToFSynth: options -> cow, cup plan and per-frame states (once), then one pure render per frame.
#include "trailscope/tof/synth.hpp"

#include <tbb/parallel_for.h>

#include <cmath>
#include <string>

#include "render.hpp"
#include "rng.hpp"
#include "scenario.hpp"
#include "scene.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"

namespace trailscope::tof {

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
  // Saturation is 30000 units (SensorParams): 0.5 units per count keeps it within 16 bits.
  s.info.amplitude_scale = 0.5;
  s.info.has_amplitude = true;
  s.info.has_truth = o.scenario != Scenario::plane;
  s.info.source = {{"generator", "trailscope synth"},
                   {"scenario", std::string(to_string(o.scenario))},
                   {"seed", o.seed},
                   {"noise_free", o.noise_free}};
  s.params = synth::scenario_params(o.scenario);
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
  const synth::SceneFrame scene =
      synth::build_scene(s.cow, s.states[index], s.params, s.options.scenario, s.info.intrinsics);
  synth::Rng rng(s.options.seed, 0x100000000ull + index);
  DepthFrame frame;
  frame.timestamp_s = static_cast<double>(index) / s.options.fps;
  FrameTruth truth;
  synth::render_frame(scene, s.info.intrinsics, s.params.sensor, s.options.noise_free, rng, frame,
                      s.info.has_truth ? &truth : nullptr);
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
