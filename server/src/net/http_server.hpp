#pragma once
// The HTTP/WebSocket server: a listener accepting on one address, one coroutine per connection, N threads
// on one io_context, and a clean stop on SIGINT/SIGTERM. Timeouts come from limits.hpp, body limits and
// WebSocket endpoints from the route table (routes/router.hpp).
// A connection's requests are read and answered one at a time, in order: pipelined requests wait in the
// socket, so no per-connection queue can grow.
#include <string>

#include "routes/app.hpp"
#include "routes/router.hpp"

namespace trailscope::server {

class WsHub;
class ReplayManager;
class BundleStreams;

struct ServerOptions {
  std::string host = "127.0.0.1";
  unsigned short port = 8080;  ///< 0 picks a free port
  unsigned threads = 2;
};

/// Serves `router` until SIGINT/SIGTERM. `on_listening(port)` is called once the socket is bound.
/// Bodies of routes whose BodyRule says so stream to `upload_dir` instead of memory. WebSocket upgrades
/// of WebSocketKind::events join `hub`; those of WebSocketKind::replay become viewers of the replay
/// {replay} of `replays` (none when null); those of WebSocketKind::bundle_stream become bundle streams of
/// `streams` (refused with 404 naming the endpoint when null).
/// Throws Error(internal) when the address cannot be bound.
void run_http_server(const ServerOptions& opts, const Router& router, WsHub& hub,
                     const std::filesystem::path& upload_dir,
                     const std::function<void(unsigned short)>& on_listening,
                     ReplayManager* replays = nullptr, BundleStreams* streams = nullptr);

}  // namespace trailscope::server
