// libFuzzer harness: the replay WebSocket control messages (server/src/replay/replay_control.cpp). The
// first byte sets the video's frame count (1..256), the rest is a conversation, one message per line,
// applied in order to one viewer's ReplayPlayback with apply_replay_control(). After every message the
// cursor is a frame of the video and the speed is in range.
#include "fuzz_support.hpp"
#include "replay/replay_control.hpp"

using namespace trailscope;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::size_t total = std::size_t{data[0]} + 1;
  std::string_view rest = fuzz::bytes_of(data + 1, size - 1);
  server::ReplayPlayback p;
  while (!rest.empty()) {
    const auto nl = rest.find('\n');
    const std::string msg(rest.substr(0, nl));
    rest = nl == std::string_view::npos ? std::string_view() : rest.substr(nl + 1);
    const auto err = server::apply_replay_control(msg, total, p);
    if (err && (!err->is_object() || !err->contains("param"))) std::abort();
    if (p.cursor >= total || (p.want && *p.want >= total) || !(p.speed >= server::kMinReplaySpeed) ||
        !(p.speed <= server::kMaxReplaySpeed))
      std::abort();
  }
  return 0;
}
