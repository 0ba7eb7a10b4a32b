#pragma once
// The embedded store: every dataset is a folder of column files under <root>/datasets/<id>/, written
// into <root>/tmp/ first and renamed into place, so a dataset appears whole or not at all: a crash or a
// kill mid-write leaves only a temporary folder, removed at the next start. All datasets are loaded into
// memory (columnar TrailSets) the first time they are asked for; later reads never touch the disk.
#include <filesystem>
#include <map>
#include <mutex>

#include "store/dataset_store.hpp"

namespace trailscope::server {

class EmbeddedStore final : public DatasetStore {
 public:
  /// What opening does with tmp/ and uploads/ (leftovers of interrupted writes and uploads).
  enum class Leftovers {
    keep,    ///< the CLI verbs: a server may be running on the same folder, mid-write or mid-upload
    remove,  ///< `serve`, the one owner of a data folder: nothing in them belongs to anyone any more
  };
  /// Opens (creating if needed) the store at `root`, removes leftovers when asked, and notes every
  /// complete dataset; each is loaded on first get() (list() loads all). A dataset folder that fails to
  /// load is reported on stderr and skipped, never deleted. Throws Error(internal) when `root` cannot be
  /// created.
  explicit EmbeddedStore(std::filesystem::path root, Leftovers leftovers = Leftovers::keep);

  std::vector<std::shared_ptr<const Dataset>> list() const override;
  std::shared_ptr<const Dataset> get(const std::string& id) const override;
  bool contains(const std::string& id) const override;
  void put(std::shared_ptr<const Dataset> ds, const ProgressFn& progress = {}) override;
  void remove(const std::string& id) override;

  const std::filesystem::path& root() const { return root_; }
  /// Folder for streamed uploads (same filesystem as the store, so ingest can read them in place).
  std::filesystem::path upload_dir() const { return root_ / "uploads"; }

  /// Bytes of a dataset's column files: kBytesPerPoint per point (t 8, lat, lon, alt, speed, track, vrate 4
  /// each, on_ground 1), kBytesPerFlight per flight (its range, 8, and its identifiers in the manifest, at
  /// most 64), and 64 KiB for the rest of the manifest. What a disk budget grants an ingest.
  static constexpr std::uint64_t kBytesPerPoint = 33, kBytesPerFlight = 72;
  static std::uint64_t bytes_estimate(const Dataset& ds);

  /// Writes / reads one dataset folder (exposed for tests).
  static void write_dataset(const Dataset& ds, const std::filesystem::path& dir);
  static std::shared_ptr<Dataset> read_dataset(const std::filesystem::path& dir);

 private:
  std::filesystem::path root_;
  /// Reads dataset `id` if it is known but not loaded yet; nullptr when unknown or unreadable. Needs mu_.
  std::shared_ptr<const Dataset> load_locked(const std::string& id) const;

  mutable std::mutex mu_;
  /// Every known dataset; nullptr until loaded.
  mutable std::map<std::string, std::shared_ptr<const Dataset>> datasets_;
};

}  // namespace trailscope::server
