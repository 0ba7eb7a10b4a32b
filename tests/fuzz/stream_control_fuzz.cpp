// libFuzzer harness: the bundle-stream WebSocket control messages (server/src/bundle_stream/
// stream_control.cpp). The bytes are a conversation: one message per line, applied in order to one
// connection's StreamControl with apply_control(), as the session does with each text message. After
// every message the settings keep the invariants the stream relies on.
#include <cmath>

#include "bundle_stream/stream_control.hpp"
#include "fuzz_support.hpp"
#include "trailscope/core/limits.hpp"

using namespace trailscope;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string_view rest = fuzz::bytes_of(data, size);
  server::StreamControl c;
  while (!rest.empty()) {
    const auto nl = rest.find('\n');
    const std::string msg(rest.substr(0, nl));
    rest = nl == std::string_view::npos ? std::string_view() : rest.substr(nl + 1);
    try {
      server::apply_control(msg, c);
    } catch (const Error& e) {
      fuzz::refuse(e);
    }
    if (!(c.window_s >= 60 && c.fade_s >= 0 && c.fade_s <= c.window_s) || (c.t && !std::isfinite(*c.t)))
      std::abort();
  }
  return 0;
}
