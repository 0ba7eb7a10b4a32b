#pragma once
// Uploaded airspace sectors (POST /api/v1/sectors), persisted under <root>/sectors/<id>/ (a FolderStore,
// folder_store.hpp): the GeoJSON FeatureCollection as it was uploaded (sectors.geojson) and a manifest
// written last, the folder staged in tmp/ and renamed into place, so that a crash leaves a set whole or
// not at all. The upload is validated by the caller (the congestion volumes parser) before it is stored;
// a set is read back and parsed again when a congestion request names it. At most
// limits::kMaxStoredSectorSets sets are kept; one more is refused (409), since an upload must never
// disappear to make room.
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "store/folder_store.hpp"

namespace trailscope::server {

class SectorStore {
 public:
  static constexpr const char* kNoun = "sector set";  ///< in messages
  /// Opens (creating if needed) <root>/sectors and notes every complete set. A folder that fails to load
  /// is reported on stderr and skipped.
  explicit SectorStore(std::filesystem::path root);

  /// Every set's metadata, oldest first.
  std::vector<nlohmann::json> list() const;
  /// {id ("s1", ...), name, created (ISO 8601 UTC), bytes, owner, ...`figures` as put() was given them}.
  /// Throws not_found("sectors").
  nlohmann::json meta(const std::string& id) const;
  /// The stored GeoJSON text, byte for byte the upload. Throws not_found("sectors").
  std::string geojson(const std::string& id) const;
  /// Stores `geojson` (already validated) under the next id with `figures` (what the parser found: the
  /// number of sectors, their names...) in its metadata, named `name` (the id when empty) and owned by
  /// `owner` (the owner name of its creator). Throws
  /// Error(conflict, "sectors") at limits::kMaxStoredSectorSets, Error(internal) when it cannot be written.
  /// Returns the metadata.
  nlohmann::json put(const std::string& name, const std::string& geojson, nlohmann::json figures,
                     const std::string& owner = "");
  /// Throws not_found("sectors").
  void remove(const std::string& id);

 private:
  FolderStore folders_;
  mutable std::mutex mu_;  ///< serialises puts (the room check and the id) and reads against deletes
};

}  // namespace trailscope::server
