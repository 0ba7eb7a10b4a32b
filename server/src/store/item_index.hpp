#pragma once
// The in-memory index of a store's numbered items (folder_store.hpp, row_store.hpp): ids "<prefix><n>"
// numbered from 1 in creation order and never reused, not even across restarts (the high-water mark is
// persisted in the store's folder, id_counter.hpp), each with its metadata (a JSON row), oldest first.
// Every item's metadata has an "owner" (the owner name of its creator; "" for items made before owners
// were recorded, and by the CLI). Not thread-safe: the store's lock guards it.
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "store/id_counter.hpp"

namespace trailscope::server {

class ItemIndex {
 public:
  /// `noun` names an item in messages ("graph", "MOT file"). `counter_file` keeps the high-water mark
  /// (IdCounter; empty: in memory only). Throws as IdCounter.
  ItemIndex(char prefix, std::string noun, std::filesystem::path counter_file = {})
      : prefix_(prefix), noun_(std::move(noun)), counter_(std::move(counter_file)) {}

  /// The number of one of this index's ids (0 when `id` is not one).
  std::uint64_t number(const std::string& id) const;
  /// A new id, numbered after every id this index (or its counter file) has ever seen; persisted before
  /// it is returned. Throws Error(internal) when the counter cannot be written.
  std::string next_id();
  /// Records item `id` (one of number() != 0) with its metadata (given "owner": "" when it has none);
  /// later ids are numbered after it.
  void add(const std::string& id, nlohmann::json meta);
  void erase(const std::string& id);

  bool contains(const std::string& id) const { return meta_.count(id) > 0; }
  /// Throws not_found(param, "<noun> '<id>' does not exist") unless `id` is recorded.
  void check(const std::string& id, const std::string& param) const;
  /// The metadata of `id`; throws as check().
  const nlohmann::json& at(const std::string& id, const std::string& param) const;
  nlohmann::json& at(const std::string& id, const std::string& param);
  /// Every item's metadata, oldest first.
  std::vector<nlohmann::json> list() const;
  std::size_t size() const { return ids_.size(); }
  /// The oldest id ("" when empty).
  std::string oldest() const { return ids_.empty() ? std::string() : ids_.begin()->second; }

 private:
  char prefix_;
  std::string noun_;
  std::map<std::uint64_t, std::string> ids_;  ///< number → id, oldest first
  std::map<std::string, nlohmann::json> meta_;
  IdCounter counter_;
};

/// The number of a store id ("g12" → 12; 0 when it is not the prefix followed by digits).
std::uint64_t store_id_number(const std::string& id, char prefix);
/// The store id of a number ('g', 12 → "g12").
std::string store_id(char prefix, std::uint64_t n);

}  // namespace trailscope::server
