#include "routes/router.hpp"

#include <algorithm>
#include <sstream>

#include "errors/error_table.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::server {

namespace {
std::vector<std::string> segments(const std::string& path) {
  std::vector<std::string> out;
  std::string seg;
  std::istringstream in(path);
  while (std::getline(in, seg, '/'))
    if (!seg.empty()) out.push_back(seg);
  return out;
}
}  // namespace

bool match_route(const std::string& pattern, const std::string& path, PathParams& params) {
  const auto ps = segments(pattern), xs = segments(path);
  if (ps.size() != xs.size()) return false;
  PathParams found;
  for (std::size_t i = 0; i < ps.size(); ++i) {
    const std::string& p = ps[i];
    const std::string& x = xs[i];
    const auto open = p.find('{');
    if (open == std::string::npos) {
      if (p != x) return false;
      continue;
    }
    const auto close = p.find('}', open);
    const std::string prefix = p.substr(0, open), suffix = p.substr(close + 1);
    if (x.size() < prefix.size() + suffix.size() + 1) return false;
    if (x.compare(0, prefix.size(), prefix) != 0) return false;
    if (x.compare(x.size() - suffix.size(), suffix.size(), suffix) != 0) return false;
    found[p.substr(open + 1, close - open - 1)] =
        x.substr(prefix.size(), x.size() - prefix.size() - suffix.size());
  }
  params = std::move(found);
  return true;
}

Router::Route& Router::add(std::string method, std::string pattern, Handler handler, BodyRule body) {
  const Role role = method == "GET" ? Role::reader : Role::writer;
  routes_.push_back({std::move(method), std::move(pattern), std::move(handler), std::move(body),
                     WebSocketKind::none, role});
  return routes_.back();
}

Router::Route& Router::add_websocket(std::string pattern, WebSocketKind kind, Handler check) {
  routes_.push_back({"GET", std::move(pattern), std::move(check), {}, kind, Role::reader});
  return routes_.back();
}

BodyRule Router::body_rule(const std::string& method, const std::string& path) const {
  for (const Route& r : routes_) {
    PathParams params;
    if (r.websocket == WebSocketKind::none && r.method == method && match_route(r.pattern, path, params))
      return r.body;
  }
  return {};
}

Router::Upgrade Router::upgrade(Request req) const {
  Upgrade u;
  std::string endpoints;
  for (const Route& r : routes_) {
    if (r.websocket == WebSocketKind::none) continue;
    endpoints += (endpoints.empty() ? "" : " and ") + r.pattern;
    if (u.route || !match_route(r.pattern, req.path, u.params)) continue;
    try {
      if (access_) access_(req, &r);
      r.handler(req, u.params);
      u.route = &r;
    } catch (const std::exception& e) {
      u.refusal = error_response(e);
      return u;
    }
  }
  if (!u.route) u.refusal = error_response(404, "not_found", "path", "WebSocket endpoints are " + endpoints);
  return u;
}

const Router::Route* Router::find(const std::string& method, const std::string& path,
                                  PathParams& params) const {
  for (const Route& r : routes_)
    if (r.websocket == WebSocketKind::none &&
        (r.method == method || (method == "HEAD" && r.method == "GET")) &&
        match_route(r.pattern, path, params))
      return &r;
  return nullptr;
}

const Router::Route* Router::admit(Request& req, PathParams& params) const {
  const Route* route = find(req.method, req.path, params);
  if (access_) access_(req, route);
  if (route && route->precheck) route->precheck(req, params);
  return route;
}

Response Router::handle(Request req) const {
  PathParams params;
  const Route* r = nullptr;
  try {
    r = admit(req, params);
  } catch (const std::exception& e) {
    return error_response(e);
  }
  return respond(r, req, params);
}

Response Router::respond(const Route* r, const Request& req, const PathParams& params) const {
  try {
    if (r) {
      Response res = r->handler(req, params);
      res.head_only = req.method == "HEAD";
      return res;
    }
    std::string allow;
    for (const Route& route : routes_) {
      PathParams ignored;
      if (route.websocket == WebSocketKind::none && match_route(route.pattern, req.path, ignored))
        allow += (allow.empty() ? "" : ", ") + route.method;
    }
    if (!allow.empty()) {
      Response res =
          error_response(405, "method_not_allowed", "", req.method + " is not allowed on " + req.path);
      res.headers.emplace_back("Allow", allow);
      return res;
    }
    if (fallback_ && (req.method == "GET" || req.method == "HEAD")) return fallback_(req, {});
    return error_response(404, "not_found", "path", "no route for " + req.path);
  } catch (const std::exception& e) {
    return error_response(e);
  }
}

void reject_unknown_params(const Request& req, const std::vector<std::string>& allowed) {
  for (const auto& [key, value] : req.query)
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end())
      throw invalid_argument(key, "unknown query parameter '" + key + "'");
}

}  // namespace trailscope::server
