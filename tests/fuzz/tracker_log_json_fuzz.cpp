// libFuzzer harness: tracker logs through decode_log(), from seeds that are json logs; the body is
// fuzz::tracker_log_one (tracker_log_harness.hpp).
#include "tracker_log_harness.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return trailscope::fuzz::tracker_log_one(trailscope::fuzz::bytes_of(data, size));
}
