// libFuzzer harness: the body of POST /api/v1/bundles (server/src/params/bundle_body.cpp) through
// parse_bundle_request(), with the bundling parameters and the source query it reads.
#include "fuzz_support.hpp"
#include "params/bundle_body.hpp"

using namespace trailscope;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    (void)server::parse_bundle_request(std::string(fuzz::bytes_of(data, size)));
  } catch (const Error& e) {
    fuzz::refuse(e);
  }
  return 0;
}
