#pragma once
// The live replays of a server (replay.hpp), by id ("rp1", "rp2", ...): created over stored videos, each
// storing its run into the run store when it ends. Replays live in memory, but their ids are never reused,
// not even after a restart (the high-water mark is persisted, store/id_counter.hpp).
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "replay/replay.hpp"
#include "store/id_counter.hpp"

namespace trailscope::server {

class VideoStore;
class RunStore;

/// The live replays of a server: at most limits::kMaxReplays at once.
class ReplayManager {
 public:
  /// `id_file`: where the high-water mark of replay ids is kept (IdCounter; empty: in memory only).
  ReplayManager(std::shared_ptr<VideoStore> videos, std::shared_ptr<RunStore> runs,
                std::filesystem::path id_file = {});
  ~ReplayManager();  ///< stops every replay

  /// Starts a replay of stored video `video`, owned by `owner`. Throws not_found("video"),
  /// Error(conflict, "replay") at limits::kMaxReplays, and Replay's errors.
  std::shared_ptr<Replay> create(const std::string& video, const tracker::TrackerParams& params,
                                 const std::string& colormap, const std::string& owner = "");
  /// Throws not_found("replay").
  std::shared_ptr<Replay> get(const std::string& id) const;
  /// nullptr when there is none (the WebSocket upgrade answers 404 itself).
  std::shared_ptr<Replay> find(const std::string& id) const;
  std::vector<nlohmann::json> list() const;
  /// Stops the replay and closes its viewers. Throws not_found("replay").
  void remove(const std::string& id);

 private:
  std::shared_ptr<VideoStore> videos_;
  std::shared_ptr<RunStore> runs_;
  mutable std::mutex mu_;
  std::map<std::uint64_t, std::shared_ptr<Replay>> replays_;  ///< by number, oldest first
  IdCounter ids_;
};

}  // namespace trailscope::server
