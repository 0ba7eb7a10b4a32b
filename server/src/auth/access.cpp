#include "auth/access.hpp"

#include <sodium.h>

#include <algorithm>
#include <cctype>

#include "errors/error_table.hpp"
#include "limits.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::server {

namespace {

using steady = std::chrono::steady_clock;
constexpr auto kFailureWindow = std::chrono::seconds(60);
constexpr const char* kParam = "authorization";

Error unauthorized(const std::string& detail) {
  return Error(Error::Kind::unauthorized, kParam, detail);
}

bool iequals_prefix(std::string_view s, std::string_view prefix) {
  if (s.size() < prefix.size()) return false;
  for (std::size_t i = 0; i < prefix.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(s[i])) != std::tolower(static_cast<unsigned char>(prefix[i])))
      return false;
  return true;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// The value of cookie `name` in a Cookie header ("a=1; trailscope_session=...; b=2"), RFC 6265 §5.4.
std::optional<std::string> cookie_value(std::string_view header, std::string_view name) {
  while (!header.empty()) {
    const auto semi = header.find(';');
    const std::string_view pair = trim(header.substr(0, semi));
    header = semi == std::string_view::npos ? std::string_view() : header.substr(semi + 1);
    const auto eq = pair.find('=');
    if (eq != std::string_view::npos && trim(pair.substr(0, eq)) == name)
      return std::string(trim(pair.substr(eq + 1)));
  }
  return std::nullopt;
}

}  // namespace

Access::Access(std::shared_ptr<TokenStore> tokens, Clock clock)
    : tokens_(std::move(tokens)), clock_(std::move(clock)) {
  ensure_sodium();
  crypto_generichash_keygen(hash_key_);
}

steady::time_point Access::now() const {
  return clock_ ? clock_() : steady::now();
}

Access::Key Access::key_of(std::string_view text) const {
  Key out(crypto_generichash_BYTES, '\0');
  crypto_generichash(reinterpret_cast<unsigned char*>(out.data()), out.size(),
                     reinterpret_cast<const unsigned char*>(text.data()), text.size(), hash_key_,
                     sizeof hash_key_);
  return out;
}

void Access::check_failures(const std::string& remote) {
  auto it = failures_.find(remote);
  if (it == failures_.end()) return;
  const auto elapsed = now() - it->second.since;
  if (elapsed >= kFailureWindow) {
    failures_.erase(it);
    return;
  }
  if (it->second.count < limits::kMaxFailedAuthPerMinute) return;
  const auto left = std::chrono::ceil<std::chrono::seconds>(kFailureWindow - elapsed).count();
  throw RetryLater(Error::Kind::too_many_requests, kParam,
                   "too many failed token checks from this address: retry in " + std::to_string(left) + " s",
                   static_cast<int>(left));
}

void Access::fail(const std::string& remote, const std::string& detail) {
  {
    std::lock_guard lock(mu_);
    const auto t = now();
    auto it = failures_.find(remote);
    if (it == failures_.end() || t - it->second.since >= kFailureWindow) {
      if (it == failures_.end() && failures_.size() >= limits::kMaxTrackedAuthAddresses) {
        std::erase_if(failures_, [&](const auto& f) { return t - f.second.since >= kFailureWindow; });
        if (failures_.size() >= limits::kMaxTrackedAuthAddresses)  // all recent: forget the oldest window
          failures_.erase(
              std::min_element(failures_.begin(), failures_.end(),
                               [](const auto& a, const auto& b) { return a.second.since < b.second.since; }));
      }
      failures_[remote] = {t, 1};
    } else {
      ++it->second.count;
    }
  }
  throw unauthorized(detail);
}

Principal Access::verify(std::string_view token, const std::string& remote) {
  const Key key = key_of(token);
  {
    std::lock_guard lock(mu_);
    auto it = verified_.find(key);
    if (it != verified_.end()) {
      if (tokens_->find(it->second.who.token_id)) {
        verified_order_.splice(verified_order_.begin(), verified_order_, it->second.order);
        return it->second.who;
      }
      verified_order_.erase(it->second.order);  // revoked since
      verified_.erase(it);
    }
    check_failures(remote);
  }
  static const std::string invalid = "the token is not valid (mistyped, revoked or unknown)";
  const auto id = token_id_of(token);
  if (!id) fail(remote, invalid);
  auto record = tokens_->find(*id);
  if (!record) {
    tokens_->refresh(true);  // created by the CLI within the last second?
    record = tokens_->find(*id);
  }
  if (!record || !verify_token_hash(*record, token)) fail(remote, invalid);
  const Principal who{record->id, record->name, record->role};
  std::lock_guard lock(mu_);
  if (!verified_.count(key)) {
    if (verified_.size() >= limits::kMaxCachedTokens) {
      verified_.erase(verified_order_.back());
      verified_order_.pop_back();
    }
    verified_order_.push_front(key);
    verified_[key] = {who, verified_order_.begin()};
  }
  return who;
}

std::string Access::issue_login_code() {
  const std::string code = random_hex(32);
  std::lock_guard lock(mu_);
  const auto t = now();
  std::erase_if(login_codes_, [&](const auto& c) { return c.second <= t; });
  login_codes_[key_of(code)] = t + std::chrono::seconds(limits::kLoginCodeSeconds);
  return code;
}

Access::Session Access::start_session(const Principal& who, bool from_token) {
  Session s{random_hex(32), who};
  std::lock_guard lock(mu_);
  const auto t = now();
  if (sessions_.size() >= limits::kMaxSessions) {
    std::erase_if(sessions_, [&](const auto& e) { return e.second.expires <= t; });
    if (sessions_.size() >= limits::kMaxSessions)  // all live: the one that would end first goes
      sessions_.erase(std::min_element(sessions_.begin(), sessions_.end(), [](const auto& a, const auto& b) {
        return a.second.expires < b.second.expires;
      }));
  }
  sessions_[key_of(s.secret)] = {who, t + std::chrono::seconds(limits::kSessionSeconds), from_token};
  return s;
}

Access::Session Access::sign_in_with_code(const std::string& code, const std::string& remote) {
  bool valid = false;
  {
    std::lock_guard lock(mu_);
    check_failures(remote);
    auto it = login_codes_.find(key_of(code));
    if (it != login_codes_.end()) {
      valid = it->second > now();
      login_codes_.erase(it);  // once, even when it came too late
    }
  }
  if (!valid)
    fail(remote,
         "the sign-in code is not valid (used, expired or mistyped): use the URL the server printed, or a "
         "token");
  return start_session(local_user(), false);
}

Access::Session Access::sign_in_with_token(const std::string& token, const std::string& remote) {
  return start_session(verify(token, remote), true);
}

std::optional<Principal> Access::session_of(const Request& req, bool& stale) {
  const auto secret = cookie_value(req.header("cookie"), kSessionCookie);
  if (!secret || secret->empty()) return std::nullopt;
  std::lock_guard lock(mu_);
  auto it = sessions_.find(key_of(*secret));
  if (it != sessions_.end() && it->second.expires > now() &&
      (!it->second.from_token || tokens_->find(it->second.who.token_id)))
    return it->second.who;
  if (it != sessions_.end()) sessions_.erase(it);
  stale = true;
  return std::nullopt;
}

void Access::sign_out(const Request& req) {
  const auto secret = cookie_value(req.header("cookie"), kSessionCookie);
  if (!secret) return;
  std::lock_guard lock(mu_);
  sessions_.erase(key_of(*secret));
}

bool Access::revoke(const std::string& id) {
  const bool found = tokens_->revoke(id);
  std::lock_guard lock(mu_);
  for (auto it = verified_.begin(); it != verified_.end();) {
    if (it->second.who.token_id == id) {
      verified_order_.erase(it->second.order);
      it = verified_.erase(it);
    } else {
      ++it;
    }
  }
  std::erase_if(sessions_, [&](const auto& s) { return s.second.from_token && s.second.who.token_id == id; });
  return found;
}

void Access::check(Request& req, const Router::Route* route) {
  tokens_->refresh();  // a stat at most once a second: tokens the CLI created or revoked
  const bool safe = req.method == "GET" || req.method == "HEAD" || req.method == "OPTIONS";
  const Role needed = route ? route->role : (safe ? Role::anyone : Role::writer);
  req.principal = Principal{};
  bool stale = false;
  const std::string authorization = req.header("authorization");
  if (!authorization.empty()) {
    if (!iequals_prefix(authorization, "Bearer "))
      throw unauthorized("the Authorization header must be 'Bearer <token>'");
    req.principal = verify(trim(std::string_view(authorization).substr(7)), req.remote_address);
  } else if (auto who = session_of(req, stale)) {
    req.principal = *who;
  }
  if (req.principal.anonymous()) {
    if (needed == Role::anyone) return;
    if (public_reads_ && needed == Role::reader && (req.method == "GET" || req.method == "HEAD")) {
      req.principal.role = Role::reader;
      return;
    }
    throw unauthorized(
        stale ? "the session has ended (expired, signed out, or its token revoked): sign in again"
              : "this request needs a token: send 'Authorization: Bearer <token>' or sign in");
  }
  if (req.principal.role < needed)
    throw Error(Error::Kind::forbidden, kParam,
                std::string("this needs the ") + role_name(needed) + " role; token " +
                    req.principal.token_id + " ('" + req.principal.owner + "') has the " +
                    role_name(req.principal.role) + " role");
}

std::string Access::session_cookie(const std::string& secret) {
  return std::string(kSessionCookie) + "=" + secret +
         "; HttpOnly; SameSite=Strict; Path=/; Max-Age=" + std::to_string(limits::kSessionSeconds);
}

std::string Access::cleared_session_cookie() {
  return std::string(kSessionCookie) + "=; HttpOnly; SameSite=Strict; Path=/; Max-Age=0";
}

Router::AccessCheck access_check(std::shared_ptr<Access> access) {
  return
      [access = std::move(access)](Request& req, const Router::Route* route) { access->check(req, route); };
}

}  // namespace trailscope::server
