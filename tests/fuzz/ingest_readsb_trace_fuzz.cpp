// libFuzzer harness: trail ingest, format readsb_trace (compute/src/ingest/readsb*); the body is
// fuzz::ingest_one (ingest_harness.hpp).
#include "ingest_harness.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return trailscope::fuzz::ingest_one(data, size, trailscope::ingest::Format::readsb_trace);
}
