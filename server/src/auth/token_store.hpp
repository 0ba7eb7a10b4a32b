#pragma once
// API tokens: created and revoked by `trailscope token` (cli/token.cpp) and by admins over
// /api/v1/tokens, checked by the access check (auth/access.hpp).
//
// A token's text is `tsk_<id>_<secret>`: `id` is 12 lower-case hex digits (public: what `token list` shows
// and `token revoke` names), `secret` is 64 lower-case hex digits (32 bytes from libsodium's
// randombytes_buf). The store keeps, per token, {id, name, role, created, hash} where `hash` is libsodium's
// crypto_pwhash_str of the whole token text (Argon2id, the INTERACTIVE limits: 2 passes over 64 MiB): a
// copy of the file does not give the tokens back. The secret is shown once, when the token is created, and
// is never stored or logged.
//
// The file is <data-dir>/tokens.json, written atomically (a temporary file, fsync, rename) under an
// exclusive lock of <data-dir>/tokens.json.lock, so that the CLI and a running server can both write it.
// A running server sees what the CLI wrote through refresh(): it stats the file (at most once a second,
// or whenever asked to) and rereads it when its inode, size or mtime changed.
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "routes/http_types.hpp"

namespace trailscope::server {

/// Where the token store and the access check read the time (steady_clock::now when empty; tests pass
/// their own, so that expiry is tested without waiting).
using SteadyClock = std::function<std::chrono::steady_clock::time_point()>;

/// "anyone", "reader", "writer", "admin".
const char* role_name(Role role) noexcept;
/// The role called `text` (reader, writer or admin: a token never has the role `anyone`). Throws
/// invalid_argument(param, "<param> must be reader, writer or admin").
Role parse_token_role(const std::string& text, const std::string& param);

/// One stored token (never its secret).
struct TokenRecord {
  std::string id;    ///< 12 lower-case hex digits
  std::string name;  ///< the owner name the resources it creates record
  Role role = Role::reader;
  std::int64_t created = 0;  ///< Unix seconds
  std::string hash;          ///< crypto_pwhash_str of the token text (Argon2id)
  /// {"id","name","role","created"} (no hash: what `token list` and GET /api/v1/tokens show).
  nlohmann::json to_json() const;
};

/// A token just created: its record and its text, which is shown once and then forgotten.
struct IssuedToken {
  TokenRecord record;
  std::string token;  ///< tsk_<id>_<secret>
};

/// The id of a token text of the form tsk_<12 hex>_<64 hex>, or nothing when it has another form.
std::optional<std::string> token_id_of(std::string_view token);

/// True when `token` is the token `record` was made for (crypto_pwhash_str_verify: tens of milliseconds
/// and 64 MiB by design; callers cache the answer, auth/access.hpp).
bool verify_token_hash(const TokenRecord& record, std::string_view token);

/// Initialises libsodium once per process. Throws Error(internal) when it cannot.
void ensure_sodium();

/// `n` random bytes from libsodium (randombytes_buf) as 2n lower-case hex digits.
std::string random_hex(std::size_t n);

class TokenStore {
 public:
  /// Tokens kept in `file` (read now when it exists; created on the first write, with its folder); an
  /// empty path keeps them in memory only (an App without a data folder, in tests). Throws Error(internal)
  /// when the file exists but cannot be read or is malformed. `clock` times refresh().
  explicit TokenStore(std::filesystem::path file = {}, SteadyClock clock = {});

  /// A new token named `name` (1..limits::kMaxTokenNameBytes of A-Z a-z 0-9 . _ @ -) with `role` (reader,
  /// writer or admin). Throws invalid_argument("name") / invalid_argument("role"), Error(conflict, "token")
  /// when limits::kMaxTokens tokens are stored, Error(internal) when the file cannot be written.
  IssuedToken create(const std::string& name, Role role);
  /// Removes the token `id`; false when there is none. Throws Error(internal) when the file cannot be
  /// written.
  bool revoke(const std::string& id);
  /// Every token, oldest first.
  std::vector<TokenRecord> list() const;
  std::optional<TokenRecord> find(const std::string& id) const;
  /// Whether the token `id` is stored (a lookup without a copy: the access check asks it on every request).
  bool contains(const std::string& id) const;
  bool empty() const;

  /// Rereads the file when it changed since it was last read (inode, size or mtime). Unless `force`, the
  /// file is stat'ed at most once a second. A file that became unreadable or malformed keeps the tokens
  /// read before (and says so on stderr).
  void refresh(bool force = false);
  /// Counts the changes seen (writes and rereads), so that caches of verified tokens can tell.
  std::uint64_t generation() const;
  const std::filesystem::path& file() const { return file_; }

 private:
  struct Stamp {
    std::uintmax_t inode = 0, size = 0;
    std::int64_t mtime_ns = 0;
    bool exists = false;
    bool operator==(const Stamp&) const = default;
  };
  Stamp stamp() const;
  std::vector<TokenRecord> read_file() const;  // throws
  void write_file(const std::vector<TokenRecord>& tokens) const;
  /// Removes the temporary files a killed writer left beside the file; the caller holds the file lock.
  void remove_leftovers() const;
  /// Runs `change` on the tokens as the file holds them now, under the file lock, and writes the result.
  template <typename F>
  auto update(F change);

  std::chrono::steady_clock::time_point now() const;

  std::filesystem::path file_;
  SteadyClock clock_;
  mutable std::mutex mu_;
  std::vector<TokenRecord> tokens_;
  Stamp stamp_;
  std::chrono::steady_clock::time_point last_check_{};
  std::uint64_t generation_ = 0;
};

}  // namespace trailscope::server
