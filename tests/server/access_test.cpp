// Access control (auth/access.hpp, auth/token_store.hpp) through the real router: every route of the table
// walked with no token and with a reader's, a writer's and an admin's; the exact refusals; browser sessions
// and the one-time sign-in code; revocation by another process seen by a running check; what tokens.json
// holds; the limit on failed token checks.
#include <sys/stat.h>

#include <fstream>
#include <regex>

#include <gtest/gtest.h>

#include "auth/access.hpp"
#include "auth/token_store.hpp"
#include "errors/error_table.hpp"
#include "limits.hpp"
#include "routes/app.hpp"
#include "store/embedded_store.hpp"
#include "test_support.hpp"

namespace trailscope::server {
namespace {

using steady = std::chrono::steady_clock;

class AccessTest : public ::testing::Test {
 protected:
  AccessTest() {
    store = std::make_shared<EmbeddedStore>(tmp.path() / "store");
    app = std::make_unique<App>(store, store->upload_dir(), std::filesystem::path(), limits::kTileCacheBytes,
                                tmp.path() / "store");
    // The same tokens file, with a clock the test moves, so that expiry needs no waiting.
    app->access = std::make_shared<Access>(std::make_shared<TokenStore>(tokens_file(), clock), clock);
    router = make_router(*app);
    reader = app->access->tokens().create("rita", Role::reader);
    writer = app->access->tokens().create("walt", Role::writer);
    admin = app->access->tokens().create("ada", Role::admin);
  }
  std::filesystem::path tokens_file() const { return tmp.path() / "store" / "tokens.json"; }

  static Request request(const std::string& method, const std::string& path, const std::string& token = "",
                         std::string body = {}) {
    Request r;
    r.method = method, r.path = path, r.body = std::move(body), r.remote_address = "192.0.2.7";
    if (!token.empty()) r.headers["authorization"] = "Bearer " + token;
    return r;
  }
  Response send(const std::string& method, const std::string& path, const std::string& token = "",
                std::string body = {}) {
    return router.handle(request(method, path, token, std::move(body)));
  }
  Response with_cookie(const std::string& method, const std::string& path, const std::string& cookie) {
    Request r = request(method, path);
    r.headers["cookie"] = "theme=dark; " + cookie + "; lang=en";
    return router.handle(r);
  }
  static nlohmann::json body(const Response& r) { return nlohmann::json::parse(r.body); }
  static std::string header(const Response& r, const std::string& name) {
    for (const auto& [k, v] : r.headers)
      if (k == name) return v;
    return "";
  }
  static void expect_body(const Response& r, int status, const std::string& error,
                          const std::string& detail) {
    EXPECT_EQ(r.status, status) << r.body;
    EXPECT_EQ(body(r), nlohmann::json({{"error", error}, {"detail", detail}, {"param", "authorization"}}));
  }
  /// "trailscope_session=<secret>" out of a Set-Cookie value, after checking its attributes.
  static std::string session_cookie_of(const Response& r) {
    const std::string set = header(r, "Set-Cookie");
    std::smatch m;
    const std::regex re("^(trailscope_session=[0-9a-f]{64}); HttpOnly; SameSite=Strict; Path=/; Max-Age=" +
                        std::to_string(limits::kSessionSeconds) + "$");
    EXPECT_TRUE(std::regex_match(set, m, re)) << set;
    return m.size() > 1 ? m[1].str() : "";
  }

  test::TempDir tmp;
  steady::time_point now = steady::now();
  SteadyClock clock = [this] { return now; };
  std::shared_ptr<EmbeddedStore> store;
  std::unique_ptr<App> app;
  Router router;
  IssuedToken reader, writer, admin;
};

// A path that `pattern` matches, every {parameter} named "nope" (resources that do not exist: the check
// must decide before any lookup).
std::string sample_path(const std::string& pattern) {
  return std::regex_replace(pattern, std::regex(R"(\{[a-z_]+\})"), "nope");
}

const char* kNeedsToken = "this request needs a token: send 'Authorization: Bearer <token>' or sign in";

TEST_F(AccessTest, EveryRouteRefusesWhoLacksItsRole) {
  std::map<Role, int> routes_of_role;
  for (const auto& route : router.routes()) {
    ++routes_of_role[route.role];
    const std::string path = sample_path(route.pattern);
    const std::string what = route.method + " " + path;
    for (const IssuedToken* caller : std::vector<const IssuedToken*>{nullptr, &reader, &writer, &admin}) {
      const Role has = caller ? caller->record.role : Role::anyone;
      Request req = request(route.method, path, caller ? caller->token : "");
      // A WebSocket route answers its upgrade; every other route its request.
      Response res;
      if (route.websocket != WebSocketKind::none) {
        const Router::Upgrade up = router.upgrade(req);
        res = up.route ? Response::status_only(101) : up.refusal;
      } else {
        res = router.handle(req);
      }
      const std::string who = caller ? caller->record.name : "anonymous";
      if (has >= route.role) {
        EXPECT_NE(res.status, 401) << what << " as " << who << ": " << res.body;
        EXPECT_NE(res.status, 403) << what << " as " << who << ": " << res.body;
      } else if (!caller) {
        expect_body(res, 401, "unauthorized", kNeedsToken);
        EXPECT_EQ(header(res, "WWW-Authenticate"), "Bearer realm=\"trailscope\"") << what;
      } else {
        expect_body(res, 403, "forbidden",
                    std::string("this needs the ") + role_name(route.role) + " role; token " +
                        caller->record.id + " ('" + caller->record.name + "') has the " + role_name(has) +
                        " role");
      }
    }
  }
  // The walk met every role, and the destructive routes are all above reader.
  EXPECT_GT(routes_of_role[Role::anyone], 0);
  EXPECT_GT(routes_of_role[Role::reader], 0);
  EXPECT_GT(routes_of_role[Role::writer], 0);
  EXPECT_GT(routes_of_role[Role::admin], 0);
  for (const auto& route : router.routes())
    if (route.method == "DELETE" && route.pattern != "/api/v1/session")
      EXPECT_GE(route.role, Role::writer) << route.pattern;
}

TEST_F(AccessTest, AnonymousStateChangesLearnNothingAboutWhatExists) {
  // 401 where an admin gets 404 (no such dataset), 405 (no such method) or 404 (no such path).
  EXPECT_EQ(send("DELETE", "/api/v1/datasets/nope", admin.token).status, 404);
  expect_body(send("DELETE", "/api/v1/datasets/nope"), 401, "unauthorized", kNeedsToken);
  EXPECT_EQ(send("PUT", "/api/v1/datasets", admin.token).status, 405);
  expect_body(send("PUT", "/api/v1/datasets"), 401, "unauthorized", kNeedsToken);
  EXPECT_EQ(send("POST", "/api/v1/no/such/path", admin.token).status, 404);
  expect_body(send("POST", "/api/v1/no/such/path"), 401, "unauthorized", kNeedsToken);
  // A reader's DELETE of a dataset that does not exist is 403, not 404, as well.
  EXPECT_EQ(send("DELETE", "/api/v1/datasets/nope", reader.token).status, 403);
  // GET of an unknown path is the browser app's (the static-file fallback): anyone's.
  EXPECT_EQ(send("GET", "/no/such/page").status, 404);
  EXPECT_EQ(send("GET", "/api/v1/health").status, 200);
}

TEST_F(AccessTest, BadCredentialsAreRefusedEvenWhereNoneIsNeeded) {
  const std::string invalid = "the token is not valid (mistyped, revoked or unknown)";
  // Another secret for a real id (Argon2id says no), an unknown id, and text of another form.
  std::string forged = admin.token;
  forged.back() = forged.back() == '0' ? '1' : '0';
  expect_body(send("GET", "/api/v1/health", forged), 401, "unauthorized", invalid);
  expect_body(send("GET", "/api/v1/datasets", "tsk_000000000000_" + std::string(64, 'a')), 401,
              "unauthorized", invalid);
  expect_body(send("GET", "/api/v1/datasets", "hello"), 401, "unauthorized", invalid);
  Request basic = request("GET", "/api/v1/datasets");
  basic.headers["authorization"] = "Basic YWRtaW46YWRtaW4=";
  expect_body(router.handle(basic), 401, "unauthorized", "the Authorization header must be 'Bearer <token>'");
  // The scheme is case-insensitive (RFC 9110 §11.1).
  Request lower = request("GET", "/api/v1/datasets");
  lower.headers["authorization"] = "bearer " + reader.token;
  EXPECT_EQ(router.handle(lower).status, 200);
}

TEST_F(AccessTest, TokensFileHoldsHashesAndNoSecret) {
  std::ifstream in(tokens_file());
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto j = nlohmann::json::parse(text);
  EXPECT_EQ(j.at("version"), 1);
  ASSERT_EQ(j.at("tokens").size(), 3u);
  for (const IssuedToken* t : {&reader, &writer, &admin}) {
    const std::string secret = t->token.substr(t->token.rfind('_') + 1);
    ASSERT_EQ(secret.size(), 64u);
    EXPECT_EQ(text.find(secret), std::string::npos) << "the secret of " << t->record.name << " is stored";
    EXPECT_EQ(text.find(secret.substr(0, 16)), std::string::npos);
    EXPECT_TRUE(std::regex_match(t->token, std::regex("tsk_[0-9a-f]{12}_[0-9a-f]{64}"))) << t->token;
  }
  for (const auto& t : j.at("tokens")) {
    EXPECT_EQ(t.size(), 5u) << t;  // id, name, role, created, hash
    EXPECT_EQ(t.at("hash").get<std::string>().rfind("$argon2id$", 0), 0u) << t;
  }
  EXPECT_EQ(j.at("tokens")[1].at("name"), "walt");
  EXPECT_EQ(j.at("tokens")[1].at("role"), "writer");
  struct stat st {};
  ASSERT_EQ(::stat(tokens_file().c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  // A second store over the file (the CLI) reads the same tokens; each checks only against its own text.
  const TokenStore again(tokens_file());
  ASSERT_EQ(again.list().size(), 3u);
  EXPECT_TRUE(verify_token_hash(*again.find(writer.record.id), writer.token));
  EXPECT_FALSE(verify_token_hash(*again.find(writer.record.id), reader.token));
}

TEST_F(AccessTest, ARunningCheckSeesTokensTheCliCreatesAndRevokes) {
  TokenStore cli(tokens_file());  // another process's view of the same file
  const IssuedToken late = cli.create("lena", Role::writer);
  // Created a moment ago: the unknown id makes the check reread the file at once.
  EXPECT_EQ(send("DELETE", "/api/v1/datasets/nope", late.token).status, 404);
  ASSERT_TRUE(cli.revoke(late.record.id));
  ASSERT_TRUE(cli.revoke(reader.record.id));
  // Within the second the file is not stat'ed again (the reader's token is verified, and cached, here);
  // after it, both revocations count, though both tokens are in the cache of verified tokens.
  EXPECT_EQ(send("GET", "/api/v1/datasets", reader.token).status, 200);
  now += std::chrono::milliseconds(1001);
  expect_body(send("DELETE", "/api/v1/datasets/nope", late.token), 401, "unauthorized",
              "the token is not valid (mistyped, revoked or unknown)");
  EXPECT_EQ(send("GET", "/api/v1/datasets", reader.token).status, 401);
  EXPECT_EQ(send("GET", "/api/v1/datasets", writer.token).status, 200);
}

TEST_F(AccessTest, SignInWithTheOneTimeCode) {
  const std::string code = app->access->issue_login_code();
  ASSERT_TRUE(std::regex_match(code, std::regex("[0-9a-f]{64}")));
  const Response in = send("POST", "/api/v1/session", "", nlohmann::json({{"login", code}}).dump());
  ASSERT_EQ(in.status, 200) << in.body;
  EXPECT_EQ(body(in), nlohmann::json({{"owner", "local"}, {"role", "admin"}}));
  EXPECT_EQ(header(in, "Cache-Control"), "no-store");
  const std::string cookie = session_cookie_of(in);
  // The cookie is an admin's: who am I, a delete that passes the check (404: no such dataset), admin routes.
  const Response me = with_cookie("GET", "/api/v1/session", cookie);
  EXPECT_EQ(
      body(me),
      nlohmann::json({{"owner", "local"}, {"role", "admin"}, {"signed_in", true}, {"public_reads", false}}));
  EXPECT_EQ(with_cookie("DELETE", "/api/v1/datasets/nope", cookie).status, 404);
  EXPECT_EQ(with_cookie("GET", "/api/v1/tokens", cookie).status, 200);
  // The code works once.
  expect_body(
      send("POST", "/api/v1/session", "", nlohmann::json({{"login", code}}).dump()), 401, "unauthorized",
      "the sign-in code is not valid (used, expired or mistyped): use the URL the server printed, or a "
      "token");
  // Signing out ends the session; the stale cookie is then no credential.
  const Response out = with_cookie("DELETE", "/api/v1/session", cookie);
  EXPECT_EQ(out.status, 204);
  EXPECT_EQ(header(out, "Set-Cookie"), "trailscope_session=; HttpOnly; SameSite=Strict; Path=/; Max-Age=0");
  expect_body(with_cookie("DELETE", "/api/v1/datasets/nope", cookie), 401, "unauthorized",
              "the session has ended (expired, signed out, or its token revoked): sign in again");
  EXPECT_EQ(
      body(with_cookie("GET", "/api/v1/session", cookie)),
      nlohmann::json({{"owner", ""}, {"role", "anyone"}, {"signed_in", false}, {"public_reads", false}}));
}

TEST_F(AccessTest, SessionsAndCodesExpire) {
  const std::string late_code = app->access->issue_login_code();
  const std::string code = app->access->issue_login_code();
  const std::string cookie =
      session_cookie_of(send("POST", "/api/v1/session", "", nlohmann::json({{"login", code}}).dump()));
  now += std::chrono::seconds(limits::kLoginCodeSeconds);
  EXPECT_EQ(send("POST", "/api/v1/session", "", nlohmann::json({{"login", late_code}}).dump()).status, 401);
  EXPECT_EQ(with_cookie("GET", "/api/v1/datasets", cookie).status, 200);
  now += std::chrono::seconds(limits::kSessionSeconds - limits::kLoginCodeSeconds);
  EXPECT_EQ(with_cookie("GET", "/api/v1/datasets", cookie).status, 401);
}

TEST_F(AccessTest, SignInWithATokenAndLoseTheSessionWithIt) {
  const Response in = send("POST", "/api/v1/session", "", nlohmann::json({{"token", reader.token}}).dump());
  ASSERT_EQ(in.status, 200) << in.body;
  EXPECT_EQ(body(in), nlohmann::json({{"owner", "rita"}, {"role", "reader"}}));
  const std::string cookie = session_cookie_of(in);
  EXPECT_EQ(with_cookie("GET", "/api/v1/datasets", cookie).status, 200);
  EXPECT_EQ(with_cookie("DELETE", "/api/v1/datasets/nope", cookie).status, 403);
  // Sign-in bodies: exactly one of login and token; a wrong token is a 401.
  const Response both = send("POST", "/api/v1/session", "", R"({"login":"x","token":"y"})");
  EXPECT_EQ(both.status, 400);
  EXPECT_EQ(body(both).at("param"), "body");
  EXPECT_EQ(send("POST", "/api/v1/session", "", R"({"password":"x"})").status, 400);
  EXPECT_EQ(send("POST", "/api/v1/session", "", R"({"token":"tsk_nope"})").status, 401);
  // An admin revokes the token over HTTP: its session ends with it.
  EXPECT_EQ(send("DELETE", "/api/v1/tokens/" + reader.record.id, admin.token).status, 204);
  EXPECT_EQ(with_cookie("GET", "/api/v1/datasets", cookie).status, 401);
  EXPECT_EQ(send("GET", "/api/v1/datasets", reader.token).status, 401);
}

TEST_F(AccessTest, AdminsManageTokensOverHttp) {
  const Response made = send("POST", "/api/v1/tokens", admin.token,
                             nlohmann::json({{"name", "bob"}, {"role", "writer"}}).dump());
  ASSERT_EQ(made.status, 201) << made.body;
  const auto j = body(made);
  const std::string id = j.at("id"), token = j.at("token");
  EXPECT_EQ(header(made, "Location"), "/api/v1/tokens/" + id);
  EXPECT_EQ(j.at("name"), "bob");
  EXPECT_EQ(j.at("role"), "writer");
  EXPECT_EQ(token_id_of(token), id);
  EXPECT_EQ(send("DELETE", "/api/v1/datasets/nope", token).status, 404);
  // The list names every token and shows no secret or hash.
  const Response list = send("GET", "/api/v1/tokens", admin.token);
  ASSERT_EQ(list.status, 200);
  EXPECT_EQ(body(list).at("tokens").size(), 4u);
  EXPECT_EQ(list.body.find("hash"), std::string::npos);
  EXPECT_EQ(list.body.find(token.substr(17)), std::string::npos);
  EXPECT_EQ(body(list).at("tokens")[3],
            nlohmann::json({{"id", id}, {"name", "bob"}, {"role", "writer"}, {"created", j.at("created")}}));
  // Bad names and roles, revocation, and a second revocation.
  const Response bad_role =
      send("POST", "/api/v1/tokens", admin.token, nlohmann::json({{"name", "eve"}, {"role", "root"}}).dump());
  EXPECT_EQ(bad_role.status, 400);
  EXPECT_EQ(body(bad_role).at("param"), "role");
  const Response bad_name = send("POST", "/api/v1/tokens", admin.token,
                                 nlohmann::json({{"name", "e ve"}, {"role", "reader"}}).dump());
  EXPECT_EQ(bad_name.status, 400);
  EXPECT_EQ(body(bad_name).at("param"), "name");
  EXPECT_EQ(send("DELETE", "/api/v1/tokens/" + id, admin.token).status, 204);
  EXPECT_EQ(send("DELETE", "/api/v1/datasets/nope", token).status, 401);
  const Response again = send("DELETE", "/api/v1/tokens/" + id, admin.token);
  EXPECT_EQ(again.status, 404);
  EXPECT_EQ(body(again).at("param"), "token");
}

TEST_F(AccessTest, FailedChecksFromOneAddressAreLimited) {
  // Failures: unknown ids (no hashing needed) and a real id with a wrong secret (Argon2id says no).
  std::string forged = writer.token;
  forged.back() = forged.back() == '0' ? '1' : '0';
  for (int i = 0; i < limits::kMaxFailedAuthPerMinute; ++i) {
    char id[13];
    std::snprintf(id, sizeof id, "%012x", i);
    const std::string token = i == 0 ? forged : "tsk_" + std::string(id) + "_" + std::string(64, 'b');
    ASSERT_EQ(send("GET", "/api/v1/datasets", token).status, 401) << i;
  }
  // Then the address is refused without any check, even a valid token not seen before...
  const std::string detail = "too many failed token checks from this address: retry in 60 s";
  for (const auto& t : {forged, admin.token}) {
    const Response r = send("GET", "/api/v1/datasets", t);
    expect_body(r, 429, "too_many_requests", detail);
    EXPECT_EQ(header(r, "Retry-After"), "60");
  }
  // ... and a sign-in code; but tokens already verified still work, as do other addresses.
  EXPECT_EQ(send("POST", "/api/v1/session", "", R"({"login":"abc"})").status, 429);
  EXPECT_EQ(send("GET", "/api/v1/datasets", reader.token).status, 429);  // never verified yet
  Request other = request("GET", "/api/v1/datasets", reader.token);
  other.remote_address = "198.51.100.1";
  EXPECT_EQ(router.handle(other).status, 200);
  EXPECT_EQ(send("GET", "/api/v1/datasets", reader.token).status, 200);  // verified (from the other address)
  now += std::chrono::seconds(45);
  EXPECT_EQ(header(send("GET", "/api/v1/datasets", admin.token), "Retry-After"), "15");
  now += std::chrono::seconds(15);  // a new minute
  EXPECT_EQ(send("GET", "/api/v1/datasets", admin.token).status, 200);
}

TEST_F(AccessTest, PublicReadsServeReadsOnly) {
  app->access->set_public_reads(true);
  EXPECT_EQ(send("GET", "/api/v1/datasets").status, 200);
  EXPECT_EQ(send("GET", "/api/v1/jobs").status, 200);
  expect_body(send("DELETE", "/api/v1/datasets/nope"), 401, "unauthorized", kNeedsToken);
  // POSTs that only compute need a reader's token still; admin reads stay an admin's.
  expect_body(send("POST", "/api/v1/projections", "", "{}"), 401, "unauthorized", kNeedsToken);
  expect_body(send("GET", "/api/v1/tokens"), 401, "unauthorized", kNeedsToken);
  Request ws = request("GET", "/api/v1/ws");
  EXPECT_NE(router.upgrade(ws).route, nullptr);
  EXPECT_EQ(body(send("GET", "/api/v1/session")).at("public_reads"), true);
}

TEST(AccessNoDataFolder, TokensLiveInMemory) {
  test::TempDir tmp;
  auto store = std::make_shared<EmbeddedStore>(tmp.path());
  App app(store, store->upload_dir(), {}, 1 << 20);
  const Router router = make_router(app);
  const IssuedToken t = app.access->tokens().create("mem", Role::writer);
  EXPECT_FALSE(std::filesystem::exists(tmp.path() / "tokens.json"));
  Request r;
  r.method = "DELETE", r.path = "/api/v1/datasets/nope";
  EXPECT_EQ(router.handle(r).status, 401);
  r.headers["authorization"] = "Bearer " + t.token;
  EXPECT_EQ(router.handle(r).status, 404);
}

}  // namespace
}  // namespace trailscope::server
