#pragma once
// The core of every store of numbered folders (graphs, bundles, videos): an item lives in
// <root>/<folder>/<id>/, its id a letter and a number ("g12", never reused while the store is open), and
// holds a metadata file written last. An item is written whole into <root>/tmp/<noun>.<id>.<random>/ and
// renamed into place (rename(2) of a folder is atomic: after a crash it is there whole or not at all); it
// is deleted by renaming it into tmp/ first, so a crash mid-delete leaves only tmp/, which the next open
// clears. Every item's metadata stays in memory: listing reads no item. Thread-safe; a store that keeps
// more state (loaded items) guards it, and the reads of item folders, with its own lock around these calls.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "store/item_index.hpp"

namespace trailscope::server {

class FolderStore {
 public:
  struct Layout {
    std::string noun;       ///< "graph": not_found's param and message, and the prefix of tmp/ names
    std::string folder;     ///< "graphs", under the root
    char prefix = 0;        ///< 'g': ids are the prefix and a number
    std::string meta_file;  ///< "manifest.json": a folder without it is incomplete and ignored
  };
  /// An item folder's metadata as list() and meta() return it; throws when the folder is not an item of
  /// this store (it is then reported on stderr and skipped, never deleted).
  using ReadMeta = std::function<nlohmann::json(const std::filesystem::path& dir)>;

  /// Opens (creating if needed) <root>/<folder> and <root>/tmp, clears what tmp/ holds of this noun, and
  /// notes every complete item. Throws Error(internal) when a folder cannot be created.
  FolderStore(std::filesystem::path root, Layout layout, const ReadMeta& read_meta);

  /// Every item's metadata, oldest first.
  std::vector<nlohmann::json> list() const;
  /// Throws not_found(noun) ("graph 'g3' does not exist").
  nlohmann::json meta(const std::string& id) const;
  /// Throws not_found(noun) unless `id` is stored.
  void check(const std::string& id) const;
  bool contains(const std::string& id) const;
  std::size_t size() const;
  /// The id of the oldest item ("" when none).
  std::string oldest() const;
  /// The folder of item `id`.
  std::filesystem::path dir(const std::string& id) const;

  /// A new id.
  std::string next_id();
  /// The number of one of this store's ids (0 when `id` is not one).
  std::uint64_t number(const std::string& id) const;
  /// A new, empty staging folder for item `id` in tmp/. Throws Error(internal).
  std::filesystem::path stage(const std::string& id) const;
  /// Renames the staged folder into place (then fsyncs the items' folder) and records `meta`. Throws
  /// Error(internal) when the rename fails; the caller removes the staging folder.
  void publish(const std::string& id, const std::filesystem::path& staged, nlohmann::json meta);
  /// Throws not_found(noun), Error(internal) when the folder cannot be moved away.
  void remove(const std::string& id);

 private:
  const std::filesystem::path root_;
  const Layout layout_;
  mutable std::mutex mu_;
  ItemIndex index_;
};

/// The folder operations every store of folders makes (the dataset store, FolderStore).
/// A new, empty folder <tmp_dir>/<name>.<random> to write an item into. Throws Error(internal).
std::filesystem::path stage_folder(const std::filesystem::path& tmp_dir, const std::string& name);
/// Renames `staged` to `final_dir` (rename(2) of a folder is atomic: after a crash the item is there whole
/// or not at all) and fsyncs the parent. Throws Error(internal) ("cannot rename into") when it fails.
void publish_folder(const std::filesystem::path& staged, const std::filesystem::path& final_dir);
/// Renames `dir` out to `gone` (atomic), then deletes it: a crash mid-delete leaves only `gone`. Throws
/// Error(internal) ("cannot remove") when `dir` cannot be moved.
void remove_folder(const std::filesystem::path& dir, const std::filesystem::path& gone);

/// The ReadMeta of a store of column files (column_io.hpp): the folder's manifest.json, whose "magic" and
/// "version" must be `magic` and `version`; those and the `private_keys` are not part of the metadata.
FolderStore::ReadMeta manifest_meta(std::string magic, int version,
                                    std::vector<std::string> private_keys = {});

/// The few items of a store kept loaded, most recently used first (items can be large: a graph may hold
/// millions of edges). Not thread-safe: the store's lock guards it.
template <typename T>
class RecentItems {
 public:
  explicit RecentItems(std::size_t capacity) : capacity_(capacity) {}
  /// The loaded item (now the most recent), or null.
  std::shared_ptr<const T> find(const std::string& id) {
    for (const auto& [lid, item] : items_)
      if (lid == id) {
        auto found = item;
        put(id, found);
        return found;
      }
    return nullptr;
  }
  void put(const std::string& id, std::shared_ptr<const T> item) {
    erase(id);
    items_.emplace_front(id, std::move(item));
    while (items_.size() > capacity_) items_.pop_back();
  }
  /// The loaded item, else the one `read()` returns, now loaded.
  template <typename Read>
  std::shared_ptr<const T> get(const std::string& id, Read&& read) {
    if (auto found = find(id)) return found;
    std::shared_ptr<const T> item = read();
    put(id, item);
    return item;
  }
  void erase(const std::string& id) {
    items_.remove_if([&](const auto& e) { return e.first == id; });
  }

 private:
  std::size_t capacity_;
  std::list<std::pair<std::string, std::shared_ptr<const T>>> items_;
};

}  // namespace trailscope::server
