// libFuzzer harness: tracker logs (compute/src/tracker/tracker_log.cpp, proto/tracker_log.proto) through
// decode_log(), which the run upload route and `trailscope replay` use; its seeds are json logs. A log
// that decodes is encoded again in both encodings and decoded back: encode_log must accept what
// decode_log accepted (the store re-encodes uploaded runs), and the round trip must keep the frame count.
#include "fuzz_support.hpp"
#include "trailscope/tracker/tracker_log.hpp"

using namespace trailscope;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  tracker::TrackerLog log;
  try {
    log = tracker::decode_log(fuzz::bytes_of(data, size));
  } catch (const Error& e) {
    fuzz::refuse(e);
    return 0;
  }
  for (const auto enc : {tracker::LogEncoding::binary, tracker::LogEncoding::json}) {
    const tracker::TrackerLog again = tracker::decode_log(tracker::encode_log(log, enc));
    if (again.frames.size() != log.frames.size() || again.truth.size() != log.truth.size()) std::abort();
  }
  return 0;
}
