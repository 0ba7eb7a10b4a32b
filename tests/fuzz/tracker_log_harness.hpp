#pragma once
// The body of the two tracker-log harnesses (tracker_log_<encoding>_fuzz.cpp), which differ only in their
// seeds (binary or JSON logs): the bytes through decode_log() (compute/src/tracker/tracker_log.cpp,
// proto/tracker_log.proto), which the run upload route and `trailscope replay` use. A log that decodes is
// encoded again in both encodings and decoded back: encode_log must accept what decode_log accepted (the
// store re-encodes uploaded runs), and the round trip must keep the frame and truth counts.
#include "fuzz_support.hpp"
#include "trailscope/tracker/tracker_log.hpp"

namespace trailscope::fuzz {

/// One input of a tracker-log harness.
inline int tracker_log_one(std::string_view bytes) {
  tracker::TrackerLog log;
  try {
    log = tracker::decode_log(bytes);
  } catch (const Error& e) {
    refuse(e);
    return 0;
  }
  for (const auto enc : {tracker::LogEncoding::binary, tracker::LogEncoding::json}) {
    const tracker::TrackerLog again = tracker::decode_log(tracker::encode_log(log, enc));
    if (again.frames.size() != log.frames.size() || again.truth.size() != log.truth.size()) std::abort();
  }
  return 0;
}

}  // namespace trailscope::fuzz
