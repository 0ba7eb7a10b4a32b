#pragma once
// The single table of routes. Each route is a method, a path pattern with {name} segments (a segment may
// carry a literal suffix, as in {y}.png) and a handler. Handlers parse, call compute/, and serialise;
// exceptions they throw are turned into responses here, by the error table, and nowhere else.
#include <functional>
#include <string>
#include <vector>

#include "routes/http_types.hpp"

namespace trailscope::server {

class Router {
 public:
  using Handler = std::function<Response(const Request&, const PathParams&)>;
  struct Route {
    std::string method, pattern;
    Handler handler;
  };

  void add(std::string method, std::string pattern, Handler handler);
  /// Finds the route and runs it. Unknown paths give 404, a known path with another method 405; any
  /// exception becomes the error table's response.
  Response handle(const Request& req) const;
  /// Every (method, pattern) pair, for the OpenAPI consistency test.
  const std::vector<Route>& routes() const { return routes_; }
  /// A fallback (static files) tried for GET requests that no route matches.
  void set_fallback(Handler h) { fallback_ = std::move(h); }

 private:
  std::vector<Route> routes_;
  Handler fallback_;
};

/// Matches `path` against `pattern`; fills `params` on success.
bool match_route(const std::string& pattern, const std::string& path, PathParams& params);

/// Throws invalid_argument naming the first query parameter not in `allowed`, so that a typo such as
/// `t_0` is an error instead of a silently ignored filter.
void reject_unknown_params(const Request& req, const std::vector<std::string>& allowed);

}  // namespace trailscope::server
