// write_synthetic_video: render in parallel batches, write in order, so memory stays at one batch.
#include <tbb/parallel_for.h>

#include "trailscope/tof/synth.hpp"

namespace trailscope::tof {

ToFSynth write_synthetic_video(const SynthOptions& options, const std::filesystem::path& target,
                               const WriteOptions& write_options, const ProgressFn& progress) {
  ToFSynth synth(options);
  DepthVideoWriter writer(target, synth.info(), write_options);
  constexpr std::size_t kBatch = 64;  // ~14 MB of 176x144 frames; enough work to spread over the cores
  std::vector<DepthFrame> batch;
  for (std::size_t begin = 0; begin < options.frames; begin += kBatch) {
    const std::size_t end = std::min(options.frames, begin + kBatch);
    batch.resize(end - begin);
    tbb::parallel_for(begin, end, [&](std::size_t i) { batch[i - begin] = synth.render(i); });
    writer.write(batch);
    if (progress) progress(static_cast<double>(end) / options.frames, "render");
  }
  writer.finish();
  return synth;
}

}  // namespace trailscope::tof
