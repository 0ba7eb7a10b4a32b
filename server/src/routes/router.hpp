#pragma once
// The single table of routes. Each route is a method, a path pattern with {name} segments (a segment may
// carry a literal suffix, as in {y}.png) and a handler. Handlers parse, call compute/, and serialise;
// exceptions they throw are turned into responses here, by the error table, and nowhere else. A route also
// says how its request body is read (BodyRule), and WebSocket upgrades are routes too (WebSocketKind):
// the network layer (net/http_server.cpp) asks the table and names no path itself.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "limits.hpp"
#include "routes/http_types.hpp"

namespace trailscope::server {

/// How a route's request body is read: in memory, or streamed to a file (Request::body_file) so that
/// memory stays flat, with a size limit (bytes) and the name a 413 gives it ("<name> exceeds the limit of
/// 2 GiB"). A streamed body has limits::kUploadTimeoutSeconds to arrive.
/// An in-memory body must be JSON (application/json or +json) unless `media_types` names the types the
/// route takes instead (e.g. image/png, image/jpeg): either way a cross-site form can send none of them
/// without a CORS preflight (text/plain, multipart/form-data and form-urlencoded are never accepted in
/// memory), which is what keeps state-changing routes safe from simple cross-site requests.
struct BodyRule {
  std::uint64_t limit = limits::kMaxRequestBodyBytes;
  bool to_file = false;
  std::string name = "request body";
  std::vector<std::string> media_types = {};  ///< lower-case types taken instead of JSON; empty: JSON
};

/// Where a route's handler runs. `io`: on the network thread that read the request (cheap lookups and cached
/// answers). `compute`: on the bounded compute pool, behind its queue limit, with a deadline and a
/// CancelToken (Request::cancel) set when the client goes away, so that heavy work never holds a network
/// thread.
enum class Lane { io, compute };

/// The WebSocket session an upgrade route opens: job events (WsHub), a replay viewer, or a bundle stream.
enum class WebSocketKind { none, events, replay, bundle_stream };

class Router {
 public:
  using Handler = std::function<Response(const Request&, const PathParams&)>;
  struct Route {
    std::string method, pattern;
    Handler handler;
    BodyRule body;
    /// Not none: a WebSocket upgrade (GET), whose handler checks the request before the upgrade (a thrown
    /// error refuses it). Plain requests never reach it.
    WebSocketKind websocket = WebSocketKind::none;
    /// The least role a caller needs (Role in routes/http_types.hpp): by default `reader` for GET and
    /// `writer` for every other method; the table names the exceptions.
    Role role = Role::reader;
    Lane lane = Lane::io;
    /// Run on the request's header before its body is read (Router::admit), for uploads: validates the
    /// query parameters, the name and the room left with the parsers the handler uses, and throws what the
    /// handler would, so that a refused upload is refused before its body is sent. Null: none.
    using Precheck = std::function<void(const Request&, const PathParams&)>;
    Precheck precheck;
    Route& checked_first(Precheck p) {
      precheck = std::move(p);
      return *this;
    }
    Route& needs(Role r) {
      role = r;
      return *this;
    }
    Route& on(Lane l) {
      lane = l;
      return *this;
    }
  };
  /// The route of a WebSocket upgrade request, or why it is refused.
  struct Upgrade {
    const Route* route = nullptr;  ///< null: refused
    PathParams params;
    Response refusal;
  };

  /// Adds a route and returns it, so that the table can name its role and lane:
  /// `r.add("POST", "/api/v1/projections", h).on(Lane::compute);`. The reference is valid until the next add.
  Route& add(std::string method, std::string pattern, Handler handler, BodyRule body = {});
  /// A WebSocket upgrade route (GET `pattern`, role `reader`); `check` answers anything (e.g. status 101)
  /// to accept.
  Route& add_websocket(std::string pattern, WebSocketKind kind, Handler check);
  /// The access check: fills `req.principal` from the request's credentials and throws
  /// Error(unauthorized) or Error(forbidden) when `route` (null when no route matches: the check then
  /// decides by the method alone, so a state-changing request learns nothing about what exists) needs more
  /// than the caller has. make_router installs the App's; a router without one admits every caller as
  /// anonymous.
  using AccessCheck = std::function<void(Request& req, const Route* route)>;
  void set_access(AccessCheck check) { access_ = std::move(check); }
  /// The route `method` `path` reaches (HEAD reaches GET's; WebSocket routes excluded) with its path
  /// parameters, or null.
  const Route* find(const std::string& method, const std::string& path, PathParams& params) const;
  /// What is known before a body is read: finds the route of `req` (headers, no body), runs the access
  /// check and then the route's precheck. Throws as they do; returns null when no route matches.
  const Route* admit(Request& req, PathParams& params) const;
  /// Finds the route, runs the access check, then the handler. Unknown paths give 404, a known path with
  /// another method 405; any exception becomes the error table's response.
  Response handle(Request req) const;
  /// The second half of handle, for a request admit() has already admitted (the network layer admits on
  /// the header, then reads the body): runs `route`'s handler, or answers 404/405/the fallback when
  /// `route` is null; any exception becomes the error table's response.
  Response respond(const Route* route, const Request& req, const PathParams& params) const;
  /// The body rule of the route `method` `path` would reach; the default rule when none.
  BodyRule body_rule(const std::string& method, const std::string& path) const;
  /// Matches a WebSocket upgrade request and runs the access check and its route's check. Unknown paths are
  /// refused with 404 naming the WebSocket endpoints; a check's error is refused with the error table's
  /// response.
  Upgrade upgrade(Request req) const;
  /// Every (method, pattern) pair, for the OpenAPI consistency test.
  const std::vector<Route>& routes() const { return routes_; }
  /// A fallback (static files) tried for GET requests that no route matches.
  void set_fallback(Handler h) { fallback_ = std::move(h); }

 private:
  std::vector<Route> routes_;
  Handler fallback_;
  AccessCheck access_;
};

/// Matches `path` against `pattern`; fills `params` on success.
bool match_route(const std::string& pattern, const std::string& path, PathParams& params);

/// Throws invalid_argument naming the first query parameter not in `allowed`, so that a typo such as
/// `t_0` is an error instead of a silently ignored filter.
void reject_unknown_params(const Request& req, const std::vector<std::string>& allowed);

}  // namespace trailscope::server
