#pragma once
// The real router over a real store in a temporary folder, for in-process route tests.
#include <gtest/gtest.h>

#include <functional>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "auth/token_store.hpp"
#include "routes/app.hpp"
#include "store/embedded_store.hpp"
#include "test_support.hpp"
#include "limits.hpp"

namespace trailscope::server::test_routes {

/// The app's router as an admin calls it: a request that names no Authorization is sent with
/// `token` (access control is on in every route test; tests/server/access_test.cpp tests it).
struct AdminRouter {
  Router router;
  std::string token;
  AdminRouter& operator=(Router r) {
    router = std::move(r);
    return *this;
  }
  Response handle(Request r) const {
    r.headers.try_emplace("authorization", "Bearer " + token);
    return router.handle(std::move(r));
  }
  BodyRule body_rule(const std::string& method, const std::string& path) const {
    return router.body_rule(method, path);
  }
  const std::vector<Router::Route>& routes() const { return router.routes(); }
  const Router::Route* find(const std::string& method, const std::string& path, PathParams& params) const {
    return router.find(method, path, params);
  }
  /// The router itself, for a real server (its clients send `token` themselves).
  operator const Router&() const { return router; }
};

/// A small plane graph as node-link JSON: two clusters of 4 nodes, every node of one linked to every
/// node of the other (16 edges that want to bundle).
inline std::string two_clusters() {
  nlohmann::json nodes = nlohmann::json::array(), links = nlohmann::json::array();
  for (int i = 0; i < 4; ++i) {
    nodes.push_back({{"id", "a" + std::to_string(i)}, {"x", 0.0}, {"y", 10.0 * i}});
    nodes.push_back({{"id", "b" + std::to_string(i)}, {"x", 100.0}, {"y", 10.0 * i + 5}});
  }
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 4; ++k)
      links.push_back({{"source", "a" + std::to_string(i)}, {"target", "b" + std::to_string(k)}});
  return nlohmann::json{{"nodes", nodes}, {"links", links}}.dump();
}

class RouteFixture : public ::testing::Test {
 protected:
  /// An admin token in tmp/store/tokens.json, which every App the tests open over tmp/store reads.
  RouteFixture() {
    router.token = TokenStore(tmp.path() / "store" / "tokens.json").create("test-admin", Role::admin).token;
  }
  /// Stores `ds` and builds the app and its router.
  void open(std::shared_ptr<Dataset> ds) {
    store = std::make_shared<EmbeddedStore>(tmp.path() / "store");
    store->put(std::move(ds));
    app = std::make_unique<App>(store, store->upload_dir(), std::filesystem::path(), limits::kTileCacheBytes,
                                tmp.path() / "store");
    router = make_router(*app);
  }
  Response get(const std::string& path, std::map<std::string, std::string> query = {},
               std::map<std::string, std::string> headers = {}) {
    Request r;
    r.method = "GET", r.path = path, r.query = std::move(query), r.headers = std::move(headers);
    r.principal = principal;
    return router.handle(r);
  }
  /// A request with a body (POST, DELETE, ...).
  Response send(const std::string& method, const std::string& path, std::string body = {},
                std::map<std::string, std::string> query = {},
                std::map<std::string, std::string> headers = {}) {
    Request r;
    r.method = method, r.path = path, r.body = std::move(body), r.query = std::move(query);
    r.headers = std::move(headers);
    r.principal = principal;
    return router.handle(r);
  }
  static nlohmann::json body(const Response& r) { return nlohmann::json::parse(r.body); }
  static std::string header(const Response& r, const std::string& name) {
    for (const auto& [k, v] : r.headers)
      if (k == name) return v;
    return "";
  }
  /// The exact status, a JSON body, its error kind and the parameter it names, and a detail.
  static void expect_error(const Response& r, int status, const std::string& error,
                           const std::string& param) {
    EXPECT_EQ(r.status, status) << r.body;
    EXPECT_EQ(r.content_type, "application/json");
    const auto j = body(r);
    EXPECT_EQ(j.at("error"), error) << r.body;
    EXPECT_EQ(j.at("param"), param) << r.body;
    EXPECT_FALSE(j.at("detail").get<std::string>().empty());
  }

  /// Values that break naive parsers (blanks, non-finite, overflowing and hex numbers, negative zero,
  /// invalid UTF-8, a very long string), followed by `extra`: those a test's routes care about.
  static std::vector<std::string> garbage_values(std::vector<std::string> extra) {
    std::vector<std::string> v = {"",
                                  " ",
                                  "-1",
                                  "0",
                                  "1e309",
                                  "nan",
                                  "inf",
                                  "-inf",
                                  "99999999999999999999",
                                  "true",
                                  "-0",
                                  "0x10",
                                  "\xff\xfe",
                                  std::string(5000, 'x')};
    v.insert(v.end(), extra.begin(), extra.end());
    return v;
  }
  /// For each path, `rounds` GETs with 1..max_keys random `keys` set to random `values` (seeded, after
  /// `adjust`): every answer must be below 500, and an error must be {"error","detail","param"}. Returns
  /// the number of requests.
  int expect_no_server_errors(const std::vector<std::string>& paths, const std::vector<std::string>& keys,
                              const std::vector<std::string>& values, int rounds, int max_keys, unsigned seed,
                              const std::function<void(std::map<std::string, std::string>&)>& adjust = {}) {
    std::mt19937 rng(seed);
    int checked = 0;
    for (const auto& path : paths)
      for (int round = 0; round < rounds; ++round) {
        std::map<std::string, std::string> q;
        const int n = 1 + static_cast<int>(rng() % static_cast<unsigned>(max_keys));
        for (int k = 0; k < n; ++k) q[keys[rng() % keys.size()]] = values[rng() % values.size()];
        if (adjust) adjust(q);
        const Response r = get(path, q);
        EXPECT_LT(r.status, 500) << path << " " << nlohmann::json(q).dump() << " → " << r.body;
        if (r.status >= 500) return checked;
        if (r.status >= 400) {
          const auto j = body(r);
          EXPECT_TRUE(j.contains("error") && j.contains("detail") && j.contains("param")) << r.body;
        }
        ++checked;
      }
    return checked;
  }

  /// The caller of get() and send(): an admin, so that the route tests may delete what they made.
  /// (routes/ownership.hpp's rule has its own tests, with callers of each role.)
  Principal principal{"test-token", "tester", Role::admin};
  trailscope::test::TempDir tmp;
  std::shared_ptr<EmbeddedStore> store;
  std::unique_ptr<App> app;
  AdminRouter router;
};

}  // namespace trailscope::server::test_routes
