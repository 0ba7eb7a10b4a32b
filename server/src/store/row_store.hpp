#pragma once
// Items kept as a payload file and a JSON row side by side, <dir>/<id><ext> and <dir>/<id>.json, with ids
// "<prefix><n>" numbered from 1 in creation order (the MOT-file and run stores). The row is written last
// (temporary file + rename, after the payload) and removed first, so a payload without its row is an
// interrupted write or delete and is removed at the next open, as are temporary files a crash left. Rows
// stay in memory. At most limits::kMaxStoredRuns items are kept; one more is refused (409). Thread-safe.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "store/item_index.hpp"

namespace trailscope::server {

class RowStore {
 public:
  struct Kind {
    std::string dir;     ///< folder under the store root, e.g. "runs"
    char prefix = 'x';   ///< id prefix, e.g. 'r' → "r1"
    std::string ext;     ///< payload extension, e.g. ".tslog"
    std::string magic;   ///< format tag written into every row file (and checked when it is read)
    std::string noun;    ///< in messages: "run", "MOT file"
    std::string plural;  ///< in messages: "runs", "MOT files"
    std::string param;   ///< the parameter that errors name: "run", "mot"
  };

  /// Opens (creating if needed) <root>/<kind.dir>; a row that fails to load is reported on stderr and
  /// skipped. Throws Error(internal) when the folder cannot be created.
  RowStore(std::filesystem::path root, Kind kind);

  /// Every row, oldest first.
  std::vector<nlohmann::json> list() const;
  /// Throws not_found(param): "<noun> '<id>' does not exist".
  nlohmann::json meta(const std::string& id, const std::string& param) const;
  std::filesystem::path payload_path(const std::string& id) const;  ///< throws as meta()
  std::size_t size() const;
  /// Throws Error(conflict, kind.param) when `items` more cannot be stored.
  void check_room(std::size_t items = 1) const;

  /// Stores the next item: `row` gets "id", "created" (ISO 8601 UTC) and "bytes" (of the payload), then
  /// `write_payload` writes the payload file at the path it is given, then the row. A failure removes the
  /// payload and rethrows. Throws Error(conflict, kind.param) at limits::kMaxStoredRuns. Returns the row.
  nlohmann::json put(nlohmann::json row,
                     const std::function<void(const std::filesystem::path&)>& write_payload);
  /// Calls `read` with the payload's path under the store's lock, so that a delete cannot remove the file
  /// mid-read. Throws as meta().
  template <typename F>
  auto read_payload(const std::string& id, const std::string& param, F&& read) const {
    std::lock_guard lock(mu_);
    check_exists_locked(id, param);
    return read(path_of(id));
  }
  /// Throws not_found(kind.param).
  void remove(const std::string& id);

 private:
  void check_exists_locked(const std::string& id, const std::string& param) const;
  std::filesystem::path path_of(const std::string& id) const;

  std::filesystem::path dir_;
  Kind kind_;
  mutable std::mutex mu_;
  ItemIndex index_;
};

}  // namespace trailscope::server
