#pragma once
// The embedded store: every dataset is a folder of column files under <root>/datasets/<id>/, written
// into <root>/tmp/ first and renamed into place, so a dataset appears whole or not at all: a crash or a
// kill mid-write leaves only a temporary folder, removed at the next start. All datasets are loaded into
// memory at start (columnar TrailSets); reads never touch the disk.
#include <filesystem>
#include <map>
#include <mutex>

#include "store/dataset_store.hpp"

namespace trailscope::server {

class EmbeddedStore final : public DatasetStore {
 public:
  /// Opens (creating if needed) the store at `root`, removes leftovers of interrupted writes and loads
  /// every complete dataset. A dataset folder that fails to load is reported on stderr and skipped, never
  /// deleted. Throws Error(internal) when `root` cannot be created.
  explicit EmbeddedStore(std::filesystem::path root);

  std::vector<std::shared_ptr<const Dataset>> list() const override;
  std::shared_ptr<const Dataset> get(const std::string& id) const override;
  bool contains(const std::string& id) const override;
  void put(std::shared_ptr<const Dataset> ds) override;
  void remove(const std::string& id) override;

  const std::filesystem::path& root() const { return root_; }
  /// Folder for streamed uploads (same filesystem as the store, so ingest can read them in place).
  std::filesystem::path upload_dir() const { return root_ / "uploads"; }

  /// Writes / reads one dataset folder (exposed for tests).
  static void write_dataset(const Dataset& ds, const std::filesystem::path& dir);
  static std::shared_ptr<Dataset> read_dataset(const std::filesystem::path& dir);

 private:
  std::filesystem::path root_;
  mutable std::mutex mu_;
  std::map<std::string, std::shared_ptr<const Dataset>> datasets_;
};

}  // namespace trailscope::server
