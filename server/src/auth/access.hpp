#pragma once
// The access check every request and WebSocket upgrade goes through (Router::set_access), the browser
// sessions and the one-time sign-in codes.
//
// Credentials: `Authorization: Bearer tsk_...` (auth/token_store.hpp) or the session cookie
// `trailscope_session` (set by POST /api/v1/session; HttpOnly, SameSite=Strict, so pages of other sites
// neither read nor send it). The rules, in order:
//   1. a request that names a credential which is not valid is refused (401): a mistyped or revoked token
//      is an error even where none is needed. An ended session (a stale cookie) counts as no credential.
//   2. with no valid credential, a route that needs `anyone` (health, the session routes, the browser app's
//      files) is served; so are GET and HEAD of `reader` routes when the server runs with --public-reads;
//      everything else is 401, whatever the path: a state-changing request (any method but GET, HEAD and
//      OPTIONS) is refused before any route lookup can tell it whether what it names exists.
//   3. a valid credential whose role is below the route's is 403, naming the role needed.
// Errors are the error table's {"error","detail","param"} with param "authorization"; a 401 carries
// `WWW-Authenticate: Bearer realm="trailscope"`.
//
// Argon2id makes checking a token slow on purpose (tens of milliseconds, 64 MiB), so a token that passed
// is remembered in memory under a keyed BLAKE2b of its text (a per-process random key: the cache holds no
// token text, and its keys are useless outside this process) for limits::kMaxCachedTokens tokens.
// A remembered token is still looked up in the store on every use, so a revocation, here or by the CLI
// (the store rereads tokens.json within a second), takes effect at once. Each address may fail
// limits::kMaxFailedAuthPerMinute token checks a minute; then its checks are answered 429 with
// Retry-After, without running Argon2id.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <list>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>

#include "auth/token_store.hpp"
#include "routes/router.hpp"

namespace trailscope::server {

class Access {
 public:
  using Clock = SteadyClock;
  /// The name of the session cookie.
  static constexpr const char* kSessionCookie = "trailscope_session";
  /// Who a one-time sign-in code signs in: the local user who started the server, as an admin.
  static Principal local_user() { return {"login", "local", Role::admin}; }

  /// Checks requests against `tokens`. `clock` (steady_clock::now by default) times sessions, sign-in codes
  /// and the failure windows; tests pass their own.
  explicit Access(std::shared_ptr<TokenStore> tokens, Clock clock = {});

  TokenStore& tokens() { return *tokens_; }
  /// --public-reads: anonymous GET and HEAD of reader routes are served (as a reader).
  void set_public_reads(bool on) { public_reads_ = on; }
  bool public_reads() const { return public_reads_; }

  /// The access check (Router::AccessCheck): sets req.principal or throws Error(unauthorized),
  /// Error(forbidden) or RetryLater(too_many_requests), as the rules above say. `route` is null when no
  /// route matches.
  void check(Request& req, const Router::Route* route);

  /// Who the token text `token` is. Throws Error(unauthorized, "authorization") when it is not a valid
  /// token, RetryLater(too_many_requests, "authorization") when `remote` has failed too often this minute.
  Principal verify(std::string_view token, const std::string& remote);

  /// A new one-time sign-in code (64 hex digits), valid once, for limits::kLoginCodeSeconds; kept in
  /// memory only.
  std::string issue_login_code();

  /// A browser session: its secret (the cookie's value) and who it signs in.
  struct Session {
    std::string secret;
    Principal who;
  };
  /// Signs in with a one-time code (as local_user()) or with a token (as the token's owner), for
  /// limits::kSessionSeconds. Throws as verify() does (a used, expired or unknown code: 401).
  Session sign_in_with_code(const std::string& code, const std::string& remote);
  Session sign_in_with_token(const std::string& token, const std::string& remote);
  /// Ends the session whose cookie `req` carries (nothing when none).
  void sign_out(const Request& req);
  /// Revokes the token `id` (TokenStore::revoke) and forgets its verified copies and its sessions.
  bool revoke(const std::string& id);

  /// The Set-Cookie value that stores `secret` in the browser, and the one that removes it.
  static std::string session_cookie(const std::string& secret);
  static std::string cleared_session_cookie();

 private:
  using Key = std::string;  // keyed BLAKE2b-256 of a secret text (raw bytes)
  struct Cached {
    Principal who;
    std::list<Key>::iterator order;
  };
  struct SessionEntry {
    Principal who;
    std::chrono::steady_clock::time_point expires;
    bool from_token = false;  // ends with its token
  };
  struct Failures {
    std::chrono::steady_clock::time_point since;
    int count = 0;
  };

  Key key_of(std::string_view text) const;
  std::chrono::steady_clock::time_point now() const;
  /// Throws RetryLater when `remote` has used up its failures this minute. Needs mu_.
  void check_failures(const std::string& remote);
  /// Counts a failure of `remote` and throws Error(unauthorized) with `detail`.
  [[noreturn]] void fail(const std::string& remote, const std::string& detail);
  Session start_session(const Principal& who, bool from_token);
  /// The session whose cookie `req` carries; nothing when none; `stale` says a cookie named an ended one.
  std::optional<Principal> session_of(const Request& req, bool& stale);

  std::shared_ptr<TokenStore> tokens_;
  Clock clock_;
  std::atomic<bool> public_reads_{false};
  unsigned char hash_key_[32];
  std::mutex mu_;
  std::unordered_map<Key, Cached> verified_;
  std::list<Key> verified_order_;  // most recently used first
  std::unordered_map<Key, SessionEntry> sessions_;
  std::unordered_map<Key, std::chrono::steady_clock::time_point> login_codes_;  // → expiry
  std::unordered_map<std::string, Failures> failures_;
};

/// The access check of `access` as the router installs it.
Router::AccessCheck access_check(std::shared_ptr<Access> access);

}  // namespace trailscope::server
