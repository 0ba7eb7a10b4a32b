#pragma once
// Parameter sweeps (POST /api/v1/sweeps): each sweep's record, persisted as <root>/sweeps/<id>.json and
// rewritten whole (temporary file + rename) when a run is added and when the sweep ends. The runs
// themselves live in the run store, tagged with the sweep's id.
#include <cstdint>
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "store/item_index.hpp"

namespace trailscope::server {

class SweepStore {
 public:
  /// Opens (creating if needed) <root>/sweeps. A record that fails to load is reported on stderr and
  /// skipped; one that was running when the server stopped is marked "interrupted".
  explicit SweepStore(std::filesystem::path root);

  /// A new sweep: {id ("s1", ...), spec, videos, frames ({first_frame, frame_count}: the range of each video
  /// tracked, frame_count 0 = to the end), total (runs to make), runs: [], state: "running", done: false,
  /// job, created, owner (the owner name of its creator)}. Returns its id.
  std::string create(nlohmann::json spec, nlohmann::json videos, nlohmann::json frames, std::size_t total,
                     const std::string& owner = "");
  /// Sets the job that makes the sweep's runs.
  void set_job(const std::string& id, const std::string& job);
  /// Appends a stored run's id.
  void add_run(const std::string& id, const std::string& run);
  /// Ends the sweep: state "done" (done: true), "cancelled" or "failed".
  void finish(const std::string& id, const std::string& state);
  /// Throws not_found("sweep").
  nlohmann::json get(const std::string& id) const;
  /// Every sweep, oldest first.
  std::vector<nlohmann::json> list() const;

 private:
  void save_locked(const nlohmann::json& record) const;

  std::filesystem::path root_;
  mutable std::mutex mu_;
  ItemIndex sweeps_;  ///< id → record
};

}  // namespace trailscope::server
