// libFuzzer harness: the body of POST /api/v1/congestion (server/src/params/congestion_body.cpp): the
// route's JSON parse (params/json_fields.hpp's parse_json_object), then parse_congestion_request().
#include "fuzz_support.hpp"
#include "params/congestion_body.hpp"
#include "params/json_fields.hpp"

using namespace trailscope;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const auto body =
        server::parse_json_object(std::string(fuzz::bytes_of(data, size)), "body: must be a JSON object");
    const server::CongestionRequest r = server::parse_congestion_request(body);
    (void)r.compute();
  } catch (const Error& e) {
    fuzz::refuse(e);
  }
  return 0;
}
