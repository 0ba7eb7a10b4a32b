// libFuzzer harness: the depth-video manifest (compute/src/tof/manifest.cpp, schema proto/depth_video.md)
// through manifest_from_text(), which both the folder and the pack reader call on manifest.json's text.
#include "fuzz_support.hpp"
#include "tof/manifest.hpp"

using namespace trailscope;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const auto m = tof::detail::manifest_from_text(std::string(fuzz::bytes_of(data, size)), "fuzz");
    if (m.frames.size() != m.info.frame_count) std::abort();  // what the readers index by
  } catch (const Error& e) {
    fuzz::refuse(e);
  }
  return 0;
}
