#pragma once
// The server's own request/response values: what a route handler sees and returns. They carry no Beast
// types, so handlers and their tests stay free of networking code.
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "trailscope/core/json_text.hpp"
#include "trailscope/core/progress.hpp"

namespace trailscope::server {

/// What a caller may do, in increasing order: each role may do what the ones before it may. `anyone` needs
/// no token (health, the browser app's files); `reader` reads; `writer` creates, and deletes what it owns;
/// `admin` also deletes anything and manages tokens. A route names the least role it needs
/// (routes/router.hpp).
enum class Role { anyone, reader, writer, admin };

/// Who sent a request, as the access check found it: the token's id and owner name and its role, or
/// anonymous (no valid token: role `anyone`, empty owner).
struct Principal {
  std::string token_id;  ///< the public half of the token ("" when anonymous)
  std::string owner;     ///< the owner name resources record ("" when anonymous)
  Role role = Role::anyone;
  bool anonymous() const { return token_id.empty(); }
  /// True when this caller may delete or cancel what `resource_owner` created: its owner, or an admin.
  bool may_modify(const std::string& resource_owner) const {
    return role == Role::admin || (!anonymous() && owner == resource_owner);
  }
};

struct Request {
  std::string method;                          ///< "GET", "POST", ...
  std::string path;                            ///< percent-decoded path, e.g. /api/v1/datasets/demo
  std::map<std::string, std::string> query;    ///< percent-decoded query parameters (last one wins)
  std::map<std::string, std::string> headers;  ///< lower-case names
  std::string body;                            ///< small bodies
  std::filesystem::path body_file;             ///< streamed upload, when set (the handler takes ownership)
  std::string remote_address;                  ///< the client's IP address ("" in in-process tests)
  Principal principal;                         ///< set by the access check before the handler runs
  /// Set when the client has gone away or the request's deadline has passed (routes on Lane::compute);
  /// a handler passes it to the compute/ function it calls. Null on the I/O lane.
  std::shared_ptr<const CancelToken> cancel;
  std::string header(const std::string& name) const {
    auto it = headers.find(name);
    return it == headers.end() ? std::string() : it->second;
  }
};

struct Response {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers;
  /// When set, sent instead of `body` without a copy (cached tiles: the cache keeps the bytes alive).
  std::shared_ptr<const std::string> shared_body;
  /// A HEAD response: the headers of the GET, with its Content-Length, and no body on the wire.
  bool head_only = false;
  /// When set, the body is not `body` but streamed with chunked transfer encoding (exports of a window's
  /// flights): each call appends the next piece to its argument and returns false after the last piece.
  /// It runs on the connection's I/O thread, between writes, so each call must do a bounded amount of
  /// work (a few hundred kilobytes); the route checked the whole export's size before answering.
  std::function<bool(std::string&)> stream;

  /// The whole body, drawing a streamed one to its end (in-process tests and the CLI).
  std::string collect() const {
    if (!stream) return bytes();
    std::string all;
    while (stream(all)) {
    }
    return all;
  }

  const std::string& bytes() const { return shared_body ? *shared_body : body; }
  static Response json(int status, const nlohmann::json& j) {
    Response r;
    r.status = status, r.body = json_text(j);
    return r;
  }
  /// `status` (201 created, 202 accepted) with the JSON body and a Location header naming the resource.
  static Response json_at(int status, const nlohmann::json& j, const std::string& location) {
    Response r = json(status, j);
    r.headers.emplace_back("Location", location);
    return r;
  }
  static Response no_content() { return status_only(204); }
  static Response status_only(int status) {
    Response r;
    r.status = status, r.content_type.clear();
    return r;
  }
};

/// Path parameters captured by the router ({id} → value).
using PathParams = std::map<std::string, std::string>;

}  // namespace trailscope::server
