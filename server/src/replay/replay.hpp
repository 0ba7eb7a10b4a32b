#pragma once
// A live replay: the tracker runs over a stored video on a background thread (tracker::TrackerRun, which
// assembles the run's header and log), frame by frame, keeping every FrameLog in memory; viewers
// (WebSocket connections, replay_viewer.hpp) play, pause, seek, step and change speed on their own cursors
// over the frames computed so far and wait for those not yet computed. When the run ends its log goes into
// the run store and every viewer is told ({"type":"run"}). The wire protocol is proto/replay_ws.md; its
// frame message is encoded by formats/replay_frame.hpp, and the replays of a server are kept by
// ReplayManager (replay_manager.hpp).
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "trailscope/density/colormap.hpp"
#include "trailscope/tof/depth_render.hpp"
#include "trailscope/tof/depth_video_io.hpp"
#include "trailscope/tracker/tracker_log.hpp"

namespace trailscope::server {

class RunStore;

/// What a replay tells its viewers from other threads. Implementations post to their own executor.
class ReplayListener {
 public:
  virtual ~ReplayListener() = default;
  /// The run's log was stored as `run`.
  virtual void on_run(const std::string& run) = 0;
  /// The replay is being deleted: close the connection.
  virtual void on_close() = 0;
};

class Replay {
 public:
  /// Opens the video, fixes the depth colour range from its first frames (2nd..98th percentile of up to
  /// 10 frames) and starts tracking. `owner`: the owner name of its creator, which the stored run records
  /// too. Throws Error(invalid_argument, "colormap") for an unknown colormap, the reader's errors for an
  /// unreadable video, Error(invalid_argument, name) for bad parameters.
  Replay(std::string id, std::string video_id, const std::filesystem::path& video,
         const tracker::TrackerParams& params, const std::string& colormap, std::shared_ptr<RunStore> runs,
         std::string owner = "");
  ~Replay();  ///< stops and joins the tracking thread
  Replay(const Replay&) = delete;
  Replay& operator=(const Replay&) = delete;

  const std::string& id() const { return id_; }
  const std::string& owner() const { return owner_; }
  std::size_t frame_count() const { return info_.frame_count; }
  /// The replay object of GET /api/v1/replays/{id}: id, video, frames, fps, width, height, params
  /// ({name: value}), colormap, depth_range_mm [min, max], created, ws, computed, done, run (the stored
  /// run's id or null), error (null or the error body of a failed run), viewers, owner.
  nlohmann::json to_json() const;
  /// tracker::header_to_json of the run's header (frame_count: the video's frames).
  nlohmann::json header_json() const;

  std::size_t computed() const;
  bool done() const;  ///< tracking ended (all frames, stopped, or failed)
  /// The timestamp of frame i, when computed.
  std::optional<double> timestamp(std::size_t i) const;
  /// The binary frame message of proto/replay_ws.md for frame i ("TSRF", JSON length, JSON, depth PNG,
  /// amplitude PNG), or nullopt when frame i is not computed yet. Reads the frame's images from the video.
  /// Thread-safe. Throws the reader's errors (e.g. the video was deleted meanwhile).
  std::optional<std::string> frame_message(std::size_t i) const;

  /// Viewers: attach/detach (thread-safe). attach() throws Error(conflict, "replay") beyond
  /// limits::kMaxReplayViewers.
  void attach(const std::shared_ptr<ReplayListener>& l);
  void detach(const ReplayListener* l);
  std::size_t viewers() const;
  /// Reserves a viewer place before a WebSocket upgrade: false when the replay is full.
  bool has_room() const;
  /// Stops tracking (the log is then not stored) and tells every viewer to close.
  void stop();

 private:
  const std::string id_, video_id_;
  tracker::TrackerParams params_;
  tof::VideoInfo info_;
  tracker::RunHeader header_;
  const density::Colormap* cmap_;
  tof::DepthRange range_;
  std::string created_;
  std::shared_ptr<RunStore> runs_;
  const std::string owner_;

  mutable std::mutex mu_;  ///< guards everything below
  std::vector<tracker::FrameLog> frames_;
  std::vector<std::optional<tof::FrameTruth>> truth_;
  bool done_ = false;
  std::string run_id_;  ///< the stored run, once tracking ended
  nlohmann::json error_ = nullptr;
  std::vector<std::weak_ptr<ReplayListener>> listeners_;

  mutable std::mutex reader_mu_;  ///< the viewers' shared reader (a reader is not thread-safe)
  std::unique_ptr<tof::DepthVideoReader> reader_;

  std::unique_ptr<tracker::TrackerRun> run_;  ///< the tracking, prepared in the constructor
  std::atomic<bool> stop_{false};
  std::thread worker_;
};

}  // namespace trailscope::server
