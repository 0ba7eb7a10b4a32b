#pragma once
// An LRU cache of rendered tiles (and of any other bytes that are a pure function of their key, such as
// encoded animation chunks), bounded in bytes. The key holds every input that changes the bytes
// (dataset and its creation stamp, z/x/y, the canonical query, value, how, cmap, size, kernel), so a hit
// can never serve a stale or foreign image.
#include <cstddef>
#include <list>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>

namespace trailscope::server {

class TileCache {
 public:
  explicit TileCache(std::size_t capacity_bytes) : capacity_(capacity_bytes) {}

  std::shared_ptr<const std::string> get(const std::string& key);
  void put(const std::string& key, std::shared_ptr<const std::string> bytes);
  /// Drops every entry whose key starts with `prefix` (a deleted dataset).
  void erase_prefix(const std::string& prefix);
  std::size_t bytes() const;
  std::size_t entries() const;

 private:
  using Entry = std::pair<std::string, std::shared_ptr<const std::string>>;
  std::size_t capacity_;
  std::size_t bytes_ = 0;
  mutable std::mutex mu_;
  std::list<Entry> lru_;  // front = most recent
  std::unordered_map<std::string, std::list<Entry>::iterator> index_;
};

}  // namespace trailscope::server
