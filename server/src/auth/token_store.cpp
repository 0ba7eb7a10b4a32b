#include "auth/token_store.hpp"

#include <sodium.h>
#include <sys/file.h>
#include <sys/stat.h>

#include <algorithm>
#include <ctime>
#include <fstream>
#include <iostream>

#include "limits.hpp"
#include "store/column_io.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"

namespace trailscope::server {
namespace fs = std::filesystem;

namespace {

constexpr std::string_view kPrefix = "tsk_";
constexpr std::size_t kIdHexDigits = 12;      // 6 random bytes: ids are public, only unique
constexpr std::size_t kSecretHexDigits = 64;  // 32 random bytes

bool lower_hex(std::string_view s) {
  return std::all_of(s.begin(), s.end(),
                     [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); });
}

void check_name(const std::string& name) {
  const bool ok = !name.empty() && name.size() <= limits::kMaxTokenNameBytes &&
                  std::all_of(name.begin(), name.end(), [](char c) {
                    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                           c == '.' || c == '_' || c == '@' || c == '-';
                  });
  if (!ok)
    throw invalid_argument(
        "name", "name: must be 1-" + std::to_string(limits::kMaxTokenNameBytes) + " of A-Z a-z 0-9 . _ @ -");
}

TokenRecord record_from_json(const nlohmann::json& j) {
  TokenRecord r;
  r.id = j.at("id").get<std::string>();
  r.name = j.at("name").get<std::string>();
  r.role = parse_token_role(j.at("role").get<std::string>(), "role");
  r.created = j.at("created").get<std::int64_t>();
  r.hash = j.at("hash").get<std::string>();
  if (r.id.size() != kIdHexDigits || !lower_hex(r.id))
    throw std::runtime_error("bad token id '" + r.id + "'");
  return r;
}

// An exclusive flock on <file>.lock for the lifetime of the object: the CLI and a running server
// read-modify-write tokens.json one at a time.
class FileLock {
 public:
  explicit FileLock(const fs::path& path) {
    fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0600);
    if (fd_ < 0) throw column_io::io_error(path, "open the lock file");
    if (::flock(fd_, LOCK_EX) != 0) {
      ::close(fd_);
      throw column_io::io_error(path, "lock");
    }
  }
  ~FileLock() {
    ::flock(fd_, LOCK_UN);
    ::close(fd_);
  }
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace

const char* role_name(Role role) noexcept {
  switch (role) {
    case Role::anyone:
      return "anyone";
    case Role::reader:
      return "reader";
    case Role::writer:
      return "writer";
    case Role::admin:
      return "admin";
  }
  return "anyone";
}

Role parse_token_role(const std::string& text, const std::string& param) {
  if (text == "reader") return Role::reader;
  if (text == "writer") return Role::writer;
  if (text == "admin") return Role::admin;
  throw invalid_argument(param, param + " must be reader, writer or admin");
}

nlohmann::json TokenRecord::to_json() const {
  return {{"id", id}, {"name", name}, {"role", role_name(role)}, {"created", created}};
}

void ensure_sodium() {
  static const int rc = sodium_init();  // thread-safe once; 1 = already initialised
  if (rc < 0) throw Error(Error::Kind::internal, "", "libsodium could not be initialised");
}

std::string random_hex(std::size_t n) {
  ensure_sodium();
  std::vector<unsigned char> bytes(n);
  randombytes_buf(bytes.data(), n);
  std::string hex(2 * n + 1, '\0');
  sodium_bin2hex(hex.data(), hex.size(), bytes.data(), n);
  sodium_memzero(bytes.data(), n);
  hex.pop_back();
  return hex;
}

std::optional<std::string> token_id_of(std::string_view token) {
  if (token.size() != kPrefix.size() + kIdHexDigits + 1 + kSecretHexDigits) return std::nullopt;
  if (token.substr(0, kPrefix.size()) != kPrefix) return std::nullopt;
  const std::string_view id = token.substr(kPrefix.size(), kIdHexDigits);
  if (token[kPrefix.size() + kIdHexDigits] != '_') return std::nullopt;
  const std::string_view secret = token.substr(kPrefix.size() + kIdHexDigits + 1);
  if (!lower_hex(id) || !lower_hex(secret)) return std::nullopt;
  return std::string(id);
}

bool verify_token_hash(const TokenRecord& record, std::string_view token) {
  ensure_sodium();
  return crypto_pwhash_str_verify(record.hash.c_str(), token.data(), token.size()) == 0;
}

TokenStore::TokenStore(fs::path file, SteadyClock clock) : file_(std::move(file)), clock_(std::move(clock)) {
  ensure_sodium();
  if (file_.empty()) return;
  if (fs::exists(file_.parent_path())) {
    FileLock file_lock(fs::path(file_.string() + ".lock"));
    remove_leftovers();
  }
  stamp_ = stamp();
  tokens_ = read_file();
  last_check_ = now();
}

void TokenStore::remove_leftovers() const {
  // Temporary files of a writer that was killed (none can be live: the caller holds the file lock). They
  // hold token hashes, so they go at the next open, not only at the next write.
  std::error_code ec;
  const std::string leftover = file_.filename().string() + ".tmp.";
  for (const auto& e : fs::directory_iterator(file_.parent_path(), ec))
    if (e.path().filename().string().starts_with(leftover)) fs::remove(e.path(), ec);
}

std::chrono::steady_clock::time_point TokenStore::now() const {
  return clock_ ? clock_() : std::chrono::steady_clock::now();
}

TokenStore::Stamp TokenStore::stamp() const {
  struct stat st {};
  if (::stat(file_.c_str(), &st) != 0) return {};
  return {static_cast<std::uintmax_t>(st.st_ino), static_cast<std::uintmax_t>(st.st_size),
          static_cast<std::int64_t>(st.st_mtim.tv_sec) * 1'000'000'000 + st.st_mtim.tv_nsec, true};
}

std::vector<TokenRecord> TokenStore::read_file() const {
  std::vector<TokenRecord> out;
  std::error_code ec;
  if (file_.empty() || !fs::exists(file_, ec)) return out;
  std::ifstream in(file_);
  if (!in) throw Error(Error::Kind::internal, "", "cannot read " + file_.string());
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    for (const auto& t : j.at("tokens")) out.push_back(record_from_json(t));
  } catch (const std::exception& e) {
    throw Error(Error::Kind::internal, "", file_.string() + " is malformed: " + e.what());
  }
  return out;
}

void TokenStore::write_file(const std::vector<TokenRecord>& tokens) const {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& t : tokens) {
    nlohmann::json j = t.to_json();
    j["hash"] = t.hash;
    list.push_back(std::move(j));
  }
  column_io::write_file_atomic(file_, json_text({{"version", 1}, {"tokens", list}}) + "\n",
                               /*owner_only=*/true);
  column_io::fsync_path(file_.parent_path());
}

template <typename F>
auto TokenStore::update(F change) {
  std::lock_guard lock(mu_);
  if (file_.empty()) {
    auto result = change(tokens_);
    ++generation_;
    return result;
  }
  std::error_code ec;
  fs::create_directories(file_.parent_path(), ec);
  FileLock file_lock(fs::path(file_.string() + ".lock"));
  remove_leftovers();
  std::vector<TokenRecord> tokens = read_file();  // what other processes wrote counts
  auto result = change(tokens);
  write_file(tokens);
  tokens_ = std::move(tokens);
  stamp_ = stamp();
  last_check_ = now();
  ++generation_;
  return result;
}

IssuedToken TokenStore::create(const std::string& name, Role role) {
  check_name(name);
  if (role == Role::anyone) throw invalid_argument("role", "role must be reader, writer or admin");
  const std::string secret = random_hex(kSecretHexDigits / 2);
  return update([&](std::vector<TokenRecord>& tokens) {
    if (tokens.size() >= limits::kMaxTokens)
      throw Error(Error::Kind::conflict, "token",
                  "the server holds " + std::to_string(limits::kMaxTokens) + " tokens; revoke one first");
    IssuedToken t;
    do {
      t.record.id = random_hex(kIdHexDigits / 2);
    } while (
        std::any_of(tokens.begin(), tokens.end(), [&](const TokenRecord& r) { return r.id == t.record.id; }));
    t.token = std::string(kPrefix) + t.record.id + "_" + secret;
    char hash[crypto_pwhash_STRBYTES];
    if (crypto_pwhash_str(hash, t.token.data(), t.token.size(), crypto_pwhash_OPSLIMIT_INTERACTIVE,
                          crypto_pwhash_MEMLIMIT_INTERACTIVE) != 0)
      throw Error(Error::Kind::internal, "", "out of memory while hashing a token");
    t.record.name = name;
    t.record.role = role;
    t.record.created = static_cast<std::int64_t>(std::time(nullptr));
    t.record.hash = hash;
    tokens.push_back(t.record);
    return t;
  });
}

bool TokenStore::revoke(const std::string& id) {
  refresh(true);
  if (!find(id)) return false;  // nothing to write (and no data folder created for a mistyped id)
  return update([&](std::vector<TokenRecord>& tokens) {
    const auto before = tokens.size();
    std::erase_if(tokens, [&](const TokenRecord& r) { return r.id == id; });
    return tokens.size() != before;
  });
}

std::vector<TokenRecord> TokenStore::list() const {
  std::lock_guard lock(mu_);
  return tokens_;
}

std::optional<TokenRecord> TokenStore::find(const std::string& id) const {
  std::lock_guard lock(mu_);
  for (const auto& t : tokens_)
    if (t.id == id) return t;
  return std::nullopt;
}

bool TokenStore::contains(const std::string& id) const {
  std::lock_guard lock(mu_);
  return std::any_of(tokens_.begin(), tokens_.end(), [&](const TokenRecord& t) { return t.id == id; });
}

bool TokenStore::empty() const {
  std::lock_guard lock(mu_);
  return tokens_.empty();
}

std::uint64_t TokenStore::generation() const {
  std::lock_guard lock(mu_);
  return generation_;
}

void TokenStore::refresh(bool force) {
  if (file_.empty()) return;
  std::lock_guard lock(mu_);
  const auto t = now();
  if (!force && t - last_check_ < std::chrono::seconds(1)) return;
  last_check_ = t;
  const Stamp s = stamp();
  if (s == stamp_) return;
  try {
    tokens_ = read_file();
    stamp_ = s;
    ++generation_;
  } catch (const std::exception& e) {
    // Half-edited by hand, say: keep serving the tokens read before rather than locking everyone out.
    std::cerr << "tokens: keeping the tokens read before: " << e.what() << "\n";
    stamp_ = s;
  }
}

}  // namespace trailscope::server
