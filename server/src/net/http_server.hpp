#pragma once
// The HTTP/WebSocket server: a listener accepting on one address, one coroutine per connection, N threads
// on one io_context, and a clean stop on SIGINT/SIGTERM. Limits come from trailscope/core/limits.hpp.
// A connection's requests are read and answered one at a time, in order: pipelined requests wait in the
// socket, so no per-connection queue can grow.
#include <string>

#include "routes/app.hpp"
#include "routes/router.hpp"

namespace trailscope::server {

class WsHub;
class ReplayManager;

struct ServerOptions {
  std::string host = "127.0.0.1";
  unsigned short port = 8080;  ///< 0 picks a free port
  unsigned threads = 2;
};

/// Serves `router` until SIGINT/SIGTERM. `on_listening(port)` is called once the socket is bound.
/// Streamed uploads (POST /api/v1/datasets, graphs, videos, runs) go to `upload_dir` instead of memory.
/// WebSocket upgrades at /api/v1/replays/{replay}/ws become viewers of `replays` (none when null).
/// Throws Error(internal) when the address cannot be bound.
void run_http_server(const ServerOptions& opts, const Router& router, WsHub& hub,
                     const std::filesystem::path& upload_dir,
                     const std::function<void(unsigned short)>& on_listening,
                     ReplayManager* replays = nullptr);

}  // namespace trailscope::server
