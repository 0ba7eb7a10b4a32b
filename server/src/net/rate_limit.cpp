#include "net/rate_limit.hpp"

#include <algorithm>
#include <cmath>

#include <boost/asio/ip/address.hpp>

namespace trailscope::server {

std::string client_key(const std::string& address) {
  boost::system::error_code ec;
  auto a = boost::asio::ip::make_address(address, ec);
  if (ec) return address;
  if (a.is_v6() && a.to_v6().is_v4_mapped())
    return boost::asio::ip::make_address_v4(boost::asio::ip::v4_mapped, a.to_v6()).to_string();
  if (a.is_v4()) return a.to_string();
  auto bytes = a.to_v6().to_bytes();
  std::fill(bytes.begin() + 8, bytes.end(), 0);
  return boost::asio::ip::address_v6(bytes).to_string() + "/64";
}

TokenBuckets::TokenBuckets(double rate, double burst, std::size_t max_keys)
    : rate_(rate), burst_(std::max(1.0, burst)), max_keys_(std::max<std::size_t>(1, max_keys)) {}

void TokenBuckets::prune(Clock::time_point now) {
  for (auto it = buckets_.begin(); it != buckets_.end();) {
    const double refilled =
        it->second.tokens + rate_ * std::chrono::duration<double>(now - it->second.at).count();
    it = refilled >= burst_ ? buckets_.erase(it) : std::next(it);  // as good as a fresh bucket
  }
}

int TokenBuckets::take(const std::string& key, Clock::time_point now) {
  if (rate_ <= 0) return 0;
  std::lock_guard lock(mutex_);
  auto it = buckets_.find(key);
  if (it == buckets_.end()) {
    if (buckets_.size() >= max_keys_) prune(now);
    if (buckets_.size() >= max_keys_) return static_cast<int>(std::ceil(1.0 / rate_));
    it = buckets_.emplace(key, Bucket{burst_, now}).first;
  }
  Bucket& b = it->second;
  b.tokens = std::min(burst_, b.tokens + rate_ * std::chrono::duration<double>(now - b.at).count());
  b.at = now;
  if (b.tokens >= 1) {
    b.tokens -= 1;
    return 0;
  }
  return std::max(1, static_cast<int>(std::ceil((1 - b.tokens) / rate_)));
}

ConnectionCounter::Slot ConnectionCounter::acquire(const std::string& key, std::string* why) {
  std::lock_guard lock(mutex_);
  if (open_ >= total_) {
    if (why) *why = "server";
    return nullptr;
  }
  std::size_t& n = counts_[key];
  if (n >= per_key_) {
    if (why) *why = "address";
    return nullptr;
  }
  ++n, ++open_;
  return Slot(static_cast<void*>(this), [this, key](void*) { release(key); });
}

void ConnectionCounter::release(const std::string& key) {
  std::lock_guard lock(mutex_);
  --open_;
  auto it = counts_.find(key);
  if (it != counts_.end() && --it->second == 0) counts_.erase(it);
}

std::size_t ConnectionCounter::open() const {
  std::lock_guard lock(mutex_);
  return open_;
}

}  // namespace trailscope::server
