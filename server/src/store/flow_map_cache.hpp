#pragma once
// The flow maps behind the flow tiles (GET /api/v1/datasets/{dataset}/flow/{z}/{x}/{y}.png): a flow map
// (field, streamlines, CUBu bundling) is computed once per key (dataset and creation stamp, window
// filters, the level-independent flow parameters) and every tile of any zoom and level is drawn from it
// (flow::render_flow_tile). An LRU cache bounded in bytes (limits::kFlowMapCacheBytes, the maps' point
// arrays counted); a map is kept without its sector fields, which tiles do not read. Requests for a key
// whose map is being computed wait for that computation instead of starting another (a map view asks for
// a dozen tiles at once).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <future>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>

#include "trailscope/flow/flow_map.hpp"

namespace trailscope::server {

class FlowMapCache {
 public:
  using Map = std::shared_ptr<const flow::FlowMap>;
  explicit FlowMapCache(std::size_t capacity_bytes) : capacity_(capacity_bytes) {}

  /// The map under `key`: from the cache; or, when another request is computing it, that request's
  /// result once it is done; or computed now by `compute` (its sector fields then dropped) and cached.
  /// What `compute` throws reaches every request waiting for it and nothing is cached, except that a
  /// waiting request whose computing request was cancelled (the client left, its deadline passed)
  /// computes the map itself (at most twice), so it never fails for another client's cancellation.
  Map get(const std::string& key, const std::function<flow::FlowMap()>& compute);
  /// Drops every entry whose key starts with `prefix` (a deleted dataset).
  void erase_prefix(const std::string& prefix);
  std::size_t entries() const;
  std::size_t bytes() const;
  /// How many maps `compute` has produced (a cache hit or a shared computation adds none).
  std::uint64_t computed() const;

  /// The bytes counted for `m`: its polylines, the bundled copies and the per-point and per-line arrays.
  static std::size_t bytes_of(const flow::FlowMap& m);

 private:
  struct Entry {
    std::string key;
    std::uint64_t id;
    std::shared_future<Map> map;
    std::size_t bytes = 0;  ///< 0 while being computed
  };
  void evict();  // mu_ held

  std::size_t capacity_;
  std::size_t bytes_ = 0;
  std::uint64_t next_id_ = 0, computed_ = 0;
  mutable std::mutex mu_;
  std::list<Entry> lru_;  // front = most recent
  std::unordered_map<std::string, std::list<Entry>::iterator> index_;
};

}  // namespace trailscope::server
