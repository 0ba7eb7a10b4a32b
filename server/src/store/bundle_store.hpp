#pragma once
// Bundling results, persisted under <root>/bundles/<id>/ (a FolderStore, folder_store.hpp: column files,
// the manifest written last). At most limits::kMaxStoredBundles are kept: storing
// one more deletes the oldest. Metadata of every bundle stays in memory; the geometry is read on first use
// and only the most recently used few stay loaded, since one bundle can hold tens of millions of points.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "store/folder_store.hpp"
#include "trailscope/bundling/bundle.hpp"

namespace trailscope::server {

/// What the source coordinates of a bundle are (Frame::from_pixels maps bundle pixels to them).
enum class BundleUnits {
  merc32,    ///< 32-bit Web Mercator units (flight trails of a dataset): lon/lat on the wire
  epsg3857,  ///< EPSG:3857 metres (a geographic graph): lon/lat on the wire
  plane,     ///< the graph's own coordinates, passed through
};
const char* to_string(BundleUnits u) noexcept;
BundleUnits parse_bundle_units(const std::string& text);

struct StoredBundle {
  std::string id;         ///< "b1", "b2", ... (increasing: the lowest number is the oldest)
  std::string created;    ///< ISO 8601 UTC
  nlohmann::json source;  ///< {"dataset", "query", "canonical", "max_gap"} or {"graph", "name", "format"}
  std::string dataset;    ///< the dataset of a flight-trail bundle ("" for a graph): its map tiles' dataset
  BundleUnits units = BundleUnits::plane;
  std::uint64_t input_points = 0;  ///< points of the input polylines, before resampling
  std::string owner;               ///< the owner name of its creator ("" for bundles made before owners)
  bundling::Bundled bundled;

  /// The API's Bundle object: id, created, source, units, params, counts, frame, quality, times_ms,
  /// path, device, owner.
  nlohmann::json to_json() const;
};

class BundleStore {
 public:
  static constexpr const char* kNoun = "bundle";  ///< in messages
  /// Opens (creating if needed) <root>/bundles and notes every complete bundle (manifest read now, the
  /// geometry on first get()). A folder that fails to load is reported on stderr and skipped.
  explicit BundleStore(std::filesystem::path root);

  /// Metadata of every bundle (StoredBundle::to_json), oldest first.
  std::vector<nlohmann::json> list() const;
  /// Throws not_found("bundle").
  nlohmann::json meta(const std::string& id) const;
  /// The whole bundle, read from disk when not loaded. Throws not_found("bundle").
  std::shared_ptr<const StoredBundle> get(const std::string& id) const;
  /// A new id for a bundle about to be computed (ids are never reused while the store is open).
  std::string reserve_id();
  /// Writes `b` (its id from reserve_id()) whole or not at all, then deletes the oldest bundles beyond
  /// limits::kMaxStoredBundles. Returns the ids deleted.
  std::vector<std::string> put(std::shared_ptr<const StoredBundle> b);
  /// Throws not_found("bundle").
  void remove(const std::string& id);
  std::size_t size() const;

  /// Bytes of a bundle's column files: kBytesPerPoint per point (x, y, original x, original y, t and
  /// displacement as float32), kBytesPerPolyline per polyline (its offset, length and angle), and 64 KiB
  /// for the manifest. What a disk budget grants a bundle job.
  static constexpr std::uint64_t kBytesPerPoint = 24, kBytesPerPolyline = 12;
  static std::uint64_t bytes_estimate(const StoredBundle& b);

  /// Writes / reads one bundle folder (exposed for tests).
  static void write_bundle(const StoredBundle& b, const std::filesystem::path& dir);
  static std::shared_ptr<StoredBundle> read_bundle(const std::filesystem::path& dir);

 private:
  FolderStore folders_;
  mutable std::mutex mu_;  ///< guards loaded_, reads of bundle folders and put's evictions
  /// The loaded bundles (at most kLoadedBundles).
  mutable RecentItems<StoredBundle> loaded_;
};

}  // namespace trailscope::server
