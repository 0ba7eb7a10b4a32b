#pragma once
// Per-client bookkeeping of the network layer: token buckets (requests per second per address and per API
// token) and counters of open connections (per address and in all). Both are keyed by a client key
// (client_key): an IPv4 address, or the /64 prefix of an IPv6 address, since one host usually holds a whole
// /64 and could otherwise pick a fresh address per request.
#include <chrono>
#include <cstddef>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>

namespace trailscope::server {

/// The key the limits count a client by: "a.b.c.d" for IPv4 (and IPv4-mapped IPv6), "x:x:x:x::/64" for
/// IPv6, `address` itself when it does not parse ("" in in-process tests).
std::string client_key(const std::string& address);

/// Token buckets by key (Turner, "New directions in communications (or which way to the information
/// age?)", IEEE Communications Magazine 1986): each key holds up to `burst` tokens, refilled at `rate` per
/// second; a request takes one. Memory: one entry per key seen lately; entries whose bucket has refilled
/// are dropped once the table holds more than `max_keys`, and while it is still full a new key is refused
/// as if its bucket were empty (so a flood of fresh addresses cannot grow the table without bound).
/// Thread-safe.
class TokenBuckets {
 public:
  using Clock = std::chrono::steady_clock;
  /// `rate` > 0 tokens per second, `burst` >= 1. rate <= 0 turns the limit off (take always succeeds).
  TokenBuckets(double rate, double burst, std::size_t max_keys = 100000);
  /// Takes a token of `key`'s bucket at `now`: 0 when taken, else the whole seconds (>= 1) after which one
  /// will be there again (the Retry-After of the 429).
  int take(const std::string& key, Clock::time_point now = Clock::now());

 private:
  struct Bucket {
    double tokens;
    Clock::time_point at;
  };
  void prune(Clock::time_point now);
  double rate_, burst_;
  std::size_t max_keys_;
  std::mutex mutex_;
  std::unordered_map<std::string, Bucket> buckets_;
};

/// Counts open connections per key and in all. acquire() returns a slot that releases its count when the
/// last copy is destroyed, or null when `key` already holds `per_key` connections or `total` are open.
/// Thread-safe.
class ConnectionCounter {
 public:
  ConnectionCounter(std::size_t per_key, std::size_t total) : per_key_(per_key), total_(total) {}
  using Slot = std::shared_ptr<void>;
  /// Null when refused; `why` then says which cap ("address" or "server").
  Slot acquire(const std::string& key, std::string* why = nullptr);
  std::size_t open() const;

 private:
  void release(const std::string& key);
  std::size_t per_key_, total_;
  mutable std::mutex mutex_;
  std::unordered_map<std::string, std::size_t> counts_;
  std::size_t open_ = 0;
};

}  // namespace trailscope::server
