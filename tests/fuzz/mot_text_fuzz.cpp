// libFuzzer harness: MOTChallenge text (compute/src/metrics/mot_text.cpp): the same bytes as ground truth,
// as a tracker's output and as 3D points, the three parsers the metrics routes and `trailscope metrics` use.
#include "fuzz_support.hpp"
#include "trailscope/metrics/mot_text.hpp"

using namespace trailscope;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto text = fuzz::bytes_of(data, size);
  try {
    (void)metrics::parse_mot_gt(text);
  } catch (const Error& e) {
    fuzz::refuse(e);
  }
  try {
    (void)metrics::parse_mot_run(text);
  } catch (const Error& e) {
    fuzz::refuse(e);
  }
  try {
    (void)metrics::parse_points(text, "points");
  } catch (const Error& e) {
    fuzz::refuse(e);
  }
  return 0;
}
