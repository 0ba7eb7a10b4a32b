#pragma once
// The server's own request/response values: what a route handler sees and returns. They carry no Beast
// types, so handlers and their tests stay free of networking code.
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace trailscope::server {

struct Request {
  std::string method;                         ///< "GET", "POST", ...
  std::string path;                           ///< percent-decoded path, e.g. /api/v1/datasets/demo
  std::map<std::string, std::string> query;   ///< percent-decoded query parameters (last one wins)
  std::map<std::string, std::string> headers; ///< lower-case names
  std::string body;                           ///< small bodies
  std::filesystem::path body_file;            ///< streamed upload, when set (the handler takes ownership)
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

  static Response json(int status, const nlohmann::json& j) {
    return Response{status, "application/json", j.dump(), {}};
  }
  static Response no_content() { return Response{204, "", "", {}}; }
};

/// Path parameters captured by the router ({id} → value).
using PathParams = std::map<std::string, std::string>;

}  // namespace trailscope::server
