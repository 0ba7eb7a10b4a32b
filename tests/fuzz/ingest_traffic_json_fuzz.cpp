// libFuzzer harness: trail ingest, format traffic_json (compute/src/ingest/traffic_json*); the body is
// fuzz::ingest_one (ingest_harness.hpp).
#include "ingest_harness.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return trailscope::fuzz::ingest_one(data, size, trailscope::ingest::Format::traffic_json);
}
