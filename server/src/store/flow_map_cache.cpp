#include "store/flow_map_cache.hpp"

#include "trailscope/core/error.hpp"

namespace trailscope::server {

std::size_t FlowMapCache::bytes_of(const flow::FlowMap& m) {
  const auto poly = [](const bundling::Polylines& p) {
    return (p.x.size() + p.y.size()) * sizeof(double) + p.offsets.size() * sizeof(std::uint32_t);
  };
  const auto& b = m.bundled;
  return sizeof(flow::FlowMap) + poly(m.lines) + m.sector.size() * sizeof(int) +
         (m.traffic.size() + m.line_traffic.size()) * sizeof(float) + poly(b.lines) + poly(b.original) +
         (b.t.size() + b.displacement.size() + b.length.size() + b.angle.size()) * sizeof(float);
}

FlowMapCache::Map FlowMapCache::get(const std::string& key, const std::function<flow::FlowMap()>& compute) {
  for (int attempt = 0;; ++attempt) {
    std::shared_future<Map> waiting;
    std::promise<Map> mine;
    std::uint64_t id = 0;
    {
      const std::lock_guard lock(mu_);
      if (const auto it = index_.find(key); it != index_.end()) {
        lru_.splice(lru_.begin(), lru_, it->second);
        waiting = it->second->map;
      } else {
        id = ++next_id_;
        lru_.push_front(Entry{key, id, mine.get_future().share()});
        index_[key] = lru_.begin();
      }
    }
    if (id == 0) {
      try {
        return waiting.get();
      } catch (const Error& e) {
        // The computing request was cancelled (its entry is gone): compute it here.
        if (e.kind() != Error::Kind::cancelled || attempt >= 2) throw;
        continue;
      }
    }
    try {
      flow::FlowMap m = compute();
      m.field.sectors.clear();
      m.field.sectors.shrink_to_fit();
      Map shared = std::make_shared<const flow::FlowMap>(std::move(m));
      mine.set_value(shared);
      const std::lock_guard lock(mu_);
      ++computed_;
      if (const auto it = index_.find(key); it != index_.end() && it->second->id == id) {
        it->second->bytes = bytes_of(*shared);
        bytes_ += it->second->bytes;
        evict();
      }
      return shared;
    } catch (...) {
      mine.set_exception(std::current_exception());
      const std::lock_guard lock(mu_);
      if (const auto it = index_.find(key); it != index_.end() && it->second->id == id) {
        lru_.erase(it->second);
        index_.erase(it);
      }
      throw;
    }
  }
}

void FlowMapCache::evict() {
  // Least recently used first; maps being computed (bytes 0) and the most recent entry stay.
  for (auto it = std::prev(lru_.end()); bytes_ > capacity_ && it != lru_.begin();) {
    const auto prev = std::prev(it);
    if (it->bytes > 0) {
      bytes_ -= it->bytes;
      index_.erase(it->key);
      lru_.erase(it);
    }
    it = prev;
  }
}

void FlowMapCache::erase_prefix(const std::string& prefix) {
  const std::lock_guard lock(mu_);
  for (auto it = lru_.begin(); it != lru_.end();) {
    if (it->key.compare(0, prefix.size(), prefix) == 0) {
      bytes_ -= it->bytes;
      index_.erase(it->key);
      it = lru_.erase(it);
    } else {
      ++it;
    }
  }
}

std::size_t FlowMapCache::entries() const {
  const std::lock_guard lock(mu_);
  return lru_.size();
}

std::size_t FlowMapCache::bytes() const {
  const std::lock_guard lock(mu_);
  return bytes_;
}

std::uint64_t FlowMapCache::computed() const {
  const std::lock_guard lock(mu_);
  return computed_;
}

}  // namespace trailscope::server
