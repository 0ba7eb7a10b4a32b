#include "store/tile_cache.hpp"

namespace trailscope::server {

std::shared_ptr<const std::string> TileCache::get(const std::string& key) {
  std::lock_guard lock(mu_);
  auto it = index_.find(key);
  if (it == index_.end()) return nullptr;
  lru_.splice(lru_.begin(), lru_, it->second);
  return it->second->second;
}

void TileCache::put(const std::string& key, std::shared_ptr<const std::string> bytes) {
  std::lock_guard lock(mu_);
  if (bytes->size() > capacity_) return;
  if (auto it = index_.find(key); it != index_.end()) {
    bytes_ -= it->second->second->size();
    lru_.erase(it->second);
    index_.erase(it);
  }
  bytes_ += bytes->size();
  lru_.emplace_front(key, std::move(bytes));
  index_[key] = lru_.begin();
  while (bytes_ > capacity_ && !lru_.empty()) {
    bytes_ -= lru_.back().second->size();
    index_.erase(lru_.back().first);
    lru_.pop_back();
  }
}

void TileCache::erase_prefix(const std::string& prefix) {
  std::lock_guard lock(mu_);
  for (auto it = lru_.begin(); it != lru_.end();) {
    if (it->first.compare(0, prefix.size(), prefix) == 0) {
      bytes_ -= it->second->size();
      index_.erase(it->first);
      it = lru_.erase(it);
    } else {
      ++it;
    }
  }
}

std::size_t TileCache::bytes() const {
  std::lock_guard lock(mu_);
  return bytes_;
}

std::size_t TileCache::entries() const {
  std::lock_guard lock(mu_);
  return index_.size();
}

}  // namespace trailscope::server
