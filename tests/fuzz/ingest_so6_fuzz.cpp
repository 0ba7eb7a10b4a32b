// libFuzzer harness: trail ingest, format so6 (compute/src/ingest/so6*); the body is
// fuzz::ingest_one (ingest_harness.hpp).
#include "ingest_harness.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return trailscope::fuzz::ingest_one(data, size, trailscope::ingest::Format::so6);
}
