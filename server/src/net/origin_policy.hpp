#pragma once
// What a browser may make this server do: the names it answers to (the Host header; a page of another site
// whose name resolves to this server's address, "DNS rebinding", sends its own name) and the origins whose
// pages may send state-changing requests and open WebSockets (a page of another site may send a POST or a
// WebSocket handshake to any address; its browser names it in the Origin header).
#include <string>
#include <vector>

namespace trailscope::server {

class OriginPolicy {
 public:
  /// `listen_host`: the address the server listens on; `port`: its port. `server_names` (serve
  /// --server-name, "name" or "name:port"): the names the server answers to; empty: the listen address,
  /// localhost, 127.0.0.1 and [::1] with `port` or without a port (another port is refused), and, on a
  /// wildcard listen address (0.0.0.0, ::), any IP address with `port` (an IP literal never comes from DNS
  /// rebinding). A name without a port matches every port. `allowed_origins` (serve --allow-origin,
  /// "scheme://host[:port]"): origins allowed besides the server's own.
  OriginPolicy(std::string listen_host, unsigned short port, std::vector<std::string> server_names = {},
               std::vector<std::string> allowed_origins = {});

  /// Checks the Host header of a request (empty: absent). Throws Error(invalid_argument, "host") for a
  /// missing Host on HTTP/1.1 (`http11`) and Error(forbidden, "host") for a name the server does not
  /// answer to.
  void check_host(const std::string& host, bool http11) const;
  /// Checks the Origin header of a state-changing request (any method but GET, HEAD and OPTIONS) or of a
  /// WebSocket handshake: absent (a client that is not a browser) or one of the server's own origins
  /// (http or https with the request's `host`) or an allowed origin. Throws Error(forbidden, "origin")
  /// otherwise, "null" (sandboxed frames, files) included.
  void check_origin(const std::string& origin, const std::string& host) const;
  /// True for the methods check_origin applies to.
  static bool state_changing(const std::string& method);

 private:
  bool wildcard_ = false;
  unsigned short port_;
  std::vector<std::string> names_;    ///< lower-case, "host" or "host:port"
  std::vector<std::string> bare_;     ///< default names, matched by a Host without a port only
  std::vector<std::string> origins_;  ///< lower-case, no trailing slash
};

}  // namespace trailscope::server
