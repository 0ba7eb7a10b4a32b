#pragma once
// The real router over a real store in a temporary folder, for in-process route tests.
#include <gtest/gtest.h>

#include "routes/app.hpp"
#include "store/embedded_store.hpp"
#include "test_support.hpp"
#include "trailscope/core/limits.hpp"

namespace trailscope::server::test_routes {

class RouteFixture : public ::testing::Test {
 protected:
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
    return router.handle(r);
  }
  /// A request with a body (POST, DELETE, ...).
  Response send(const std::string& method, const std::string& path, std::string body = {},
                std::map<std::string, std::string> query = {},
                std::map<std::string, std::string> headers = {}) {
    Request r;
    r.method = method, r.path = path, r.body = std::move(body), r.query = std::move(query);
    r.headers = std::move(headers);
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

  trailscope::test::TempDir tmp;
  std::shared_ptr<EmbeddedStore> store;
  std::unique_ptr<App> app;
  Router router;
};

}  // namespace trailscope::server::test_routes
