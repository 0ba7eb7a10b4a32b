#pragma once
// Tracker runs (tracker logs, tracker/tracker_log.hpp), persisted as <root>/runs/<id>.tslog (binary
// protobuf, written atomically by tracker::write_log) and <root>/runs/<id>.json, the run's table row
// written last (temporary file + rename): a log without its row is an interrupted write and is removed
// at the next start. Rows stay in memory; logs are read on use, the most recently used few kept. At most
// limits::kMaxStoredRuns are kept; one more is refused (409).
#include <cstdint>
#include <filesystem>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "store/row_store.hpp"
#include "trailscope/tracker/tracker_log.hpp"

namespace trailscope::server {

/// The figures of a run's table row: {frames, fps (the video's), duration_s, tracker_fps (frames per
/// second of the tracker's own stage times; null when none were logged), track_share (share of frames in
/// TRACK), lost_episodes (maximal runs of LOST frames), has_truth, accuracy (null without ground truth,
/// else tracker::evaluate_accuracy's median_error_mm, mean_error_mm, p95_error_mm, frames_all_within,
/// within_mm, visible_pairs, reported_pairs; NaN figures are null)}.
nlohmann::json run_summary(const tracker::TrackerLog& log);

class RunStore {
 public:
  static constexpr const char* kNoun = "run";  ///< in messages
  /// Opens (creating if needed) <root>/runs; see above. A row that fails to load is reported on stderr and
  /// skipped.
  explicit RunStore(std::filesystem::path root);

  /// Every run's row (see meta()), oldest first.
  std::vector<nlohmann::json> list() const;
  /// The API's Run row: id (store id, "r1", ...), run_id (the log's own), video, origin ("upload",
  /// "track", "replay", "sweep"), sweep (the sweep's id or null), created (stored, ISO 8601 UTC), run_created
  /// (the log's), tracker_version, param_names and params (the log's parameter vector, in its order), bytes
  /// (of the .tslog), summary (run_summary) and owner (of the run's creator). Throws not_found("run").
  nlohmann::json meta(const std::string& id) const;
  /// The whole log. Throws not_found("run").
  std::shared_ptr<const tracker::TrackerLog> get(const std::string& id) const;
  /// The .tslog file (binary protobuf). Throws not_found("run").
  std::filesystem::path log_path(const std::string& id) const;
  /// Stores a log under the next id, owned by `owner`; `sweep` is the id of the sweep that made it (the
  /// row's "sweep", null when empty). Throws Error(conflict, "run") at limits::kMaxStoredRuns. Returns the
  /// row.
  nlohmann::json put(tracker::TrackerLog log, const std::string& origin, const std::string& sweep = "",
                     const std::string& owner = "");
  /// Throws Error(conflict, "run") when `runs` more runs cannot be stored (checked before long work).
  void check_room(std::size_t runs = 1) const;
  /// Throws not_found("run").
  void remove(const std::string& id);
  std::size_t size() const;

 private:
  void touch(const std::string& id, std::shared_ptr<const tracker::TrackerLog> log) const;

  RowStore rows_;
  mutable std::mutex cache_mu_;  ///< guards loaded_
  mutable std::list<std::pair<std::string, std::shared_ptr<const tracker::TrackerLog>>> loaded_;
};

}  // namespace trailscope::server
