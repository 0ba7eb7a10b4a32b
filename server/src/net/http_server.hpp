#pragma once
// The HTTP/WebSocket server: a listener accepting on one address, one coroutine per connection, N threads
// on one io_context, and a clean stop on SIGINT/SIGTERM. Timeouts come from limits.hpp, body limits and
// WebSocket endpoints from the route table (routes/router.hpp).
// A connection's requests are read and answered one at a time, in order: pipelined requests wait in the
// socket, so no per-connection queue can grow.
#include <chrono>
#include <string>
#include <vector>

#include "limits.hpp"
#include "routes/app.hpp"
#include "routes/router.hpp"

namespace trailscope::server {

class WsHub;
class ReplayManager;
class BundleStreams;

/// The network layer's admission limits; the defaults are limits.hpp's (README "Limits"), tests shrink
/// them. A rate <= 0 turns that rate limit off.
struct NetLimits {
  unsigned compute_workers = limits::kComputeWorkers;
  std::size_t max_queued_compute = limits::kMaxQueuedComputeRequests;
  std::chrono::milliseconds compute_deadline{limits::kComputeDeadlineSeconds * 1000};
  double per_address_rate = limits::kRequestsPerSecondPerAddress;
  double per_address_burst = limits::kRequestBurstPerAddress;
  double per_token_rate = limits::kRequestsPerSecondPerToken;
  double per_token_burst = limits::kRequestBurstPerToken;
  std::size_t max_connections_per_address = limits::kMaxConnectionsPerAddress;
  std::size_t max_connections = limits::kMaxConnections;
  std::chrono::milliseconds request_timeout{limits::kRequestTimeoutSeconds * 1000};
  std::chrono::milliseconds upload_timeout{limits::kUploadTimeoutSeconds * 1000};
  std::chrono::milliseconds body_rate_grace{limits::kBodyRateGraceSeconds * 1000};
  std::uint64_t min_body_bytes_per_second = limits::kMinBodyBytesPerSecond;
  std::size_t max_header_bytes = limits::kMaxRequestHeaderBytes;
};

struct ServerOptions {
  std::string host = "127.0.0.1";
  unsigned short port = 8080;  ///< 0 picks a free port
  unsigned threads = 2;
  /// Names the server answers to (the Host header; serve --server-name); empty: the listen address,
  /// localhost, 127.0.0.1 and [::1] with the port (net/origin_policy.hpp).
  std::vector<std::string> server_names;
  /// Origins besides the server's own whose pages may send state-changing requests and open WebSockets
  /// (serve --allow-origin).
  std::vector<std::string> allowed_origins;
  NetLimits limits;
};

/// What every request goes through, in order, before its handler runs (each refusal is the JSON error body,
/// then the connection is closed when a body was left unread):
///  1. the connection caps (per address and in all): 503 + Retry-After, then closed;
///  2. the header: over limits::kMaxRequestHeaderBytes 431; malformed framing (a bad or second
///     Content-Length, chunked with Content-Length, a bare LF) 400; a version other than HTTP/1.0 and 1.1
///     505; HTTP/1.1 without Host 400; a Host that is not a server name 403; a header not complete within
///     limits::kRequestTimeoutSeconds 408 (an idle keep-alive connection is closed without an answer);
///  3. the rate limit of the client's address: 429 + Retry-After;
///  4. Origin, on state-changing requests and WebSocket handshakes: 403;
///  5. Router::admit (the access check, then the route's precheck); the rate limit of the caller's token
///     (429); the body limit from Content-Length (413); a body to a route that reads its body in memory
///     (every such route takes JSON) must say Content-Type application/json or +json (415);
///  6. `Expect: 100-continue` is answered 100 only now; the body must then keep up a minimum rate after a
///     grace period (limits::kMinBodyBytesPerSecond), else 408;
///  7. Lane::compute routes run on the compute pool (net/compute_pool.hpp): a full queue 503 + Retry-After;
///     a request not finished within limits::kComputeDeadlineSeconds has its CancelToken set and is answered
///     503 + Retry-After; a client that closes its connection meanwhile has its request withdrawn from the
///     queue or its token set, and gets no answer. (A client that half-closes its sending side after the
///     request counts as gone.)
/// Every response carries X-Content-Type-Options: nosniff and Referrer-Policy: no-referrer; HTML responses
/// (the browser app) a Content-Security-Policy without inline scripts and with frame-ancestors 'none'.
///
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
