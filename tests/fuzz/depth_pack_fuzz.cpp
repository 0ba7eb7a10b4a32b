// libFuzzer harness: depth-video packs and single 16-bit PNGs (compute/src/tof/video_reader.cpp,
// png16.cpp) through DepthVideoReader on a file, as the video upload route and `trailscope video` open
// them (the reader tells a pack from a PNG by content), then every frame is decoded (at most 16, so that a
// long valid video does not slow the fuzzer) and the video described.
#include <algorithm>

#include "fuzz_support.hpp"
#include "trailscope/tof/depth_video_io.hpp"

using namespace trailscope;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static fuzz::InputFile file(".tsdv");
  try {
    const tof::DepthVideoReader reader(file.write(fuzz::bytes_of(data, size)));
    (void)tof::describe_video(reader);
    const std::size_t n = std::min<std::size_t>(reader.size(), 16);
    for (std::size_t i = 0; i < n; ++i) {
      try {
        const tof::DepthFrame f = reader.read_frame(i);
        const auto& in = reader.info().intrinsics;
        if (f.depth_mm.size() != static_cast<std::size_t>(in.width) * static_cast<std::size_t>(in.height))
          std::abort();
      } catch (const Error& e) {
        fuzz::refuse(e);  // one damaged frame: the others are still read
      }
    }
  } catch (const Error& e) {
    fuzz::refuse(e);
  }
  return 0;
}
