#pragma once
// The server's own request/response values: what a route handler sees and returns. They carry no Beast
// types, so handlers and their tests stay free of networking code.
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "trailscope/core/json_text.hpp"

namespace trailscope::server {

struct Request {
  std::string method;                          ///< "GET", "POST", ...
  std::string path;                            ///< percent-decoded path, e.g. /api/v1/datasets/demo
  std::map<std::string, std::string> query;    ///< percent-decoded query parameters (last one wins)
  std::map<std::string, std::string> headers;  ///< lower-case names
  std::string body;                            ///< small bodies
  std::filesystem::path body_file;             ///< streamed upload, when set (the handler takes ownership)
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
