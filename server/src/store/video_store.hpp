#pragma once
// Depth videos the tracker runs on, persisted under <root>/videos/<id>/: the video as one pack file
// (video.tsdv, proto/depth_video.md) and meta.json (id, name, created, bytes, origin and the video's
// description) written last (a FolderStore, folder_store.hpp: assembled in <root>/tmp/ and renamed into
// place, so after a crash it is there whole or not at all). At most limits::kMaxStoredVideos are kept; one
// more is refused (409) rather than deleting a user's upload to make room.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "store/folder_store.hpp"
#include "trailscope/core/progress.hpp"
#include "trailscope/tof/synth.hpp"

namespace trailscope::server {

class VideoStore {
 public:
  static constexpr const char* kNoun = "video";  ///< in messages
  /// Told the bytes written so far while a video is being written (after each batch of frames); throws
  /// to stop the write (a disk budget, jobs/disk_budget.hpp), which then leaves nothing behind.
  using WriteCheck = std::function<void(std::uint64_t bytes_written)>;
  /// Opens (creating if needed) <root>/videos and notes every complete video (one with meta.json);
  /// leftovers of interrupted writes in <root>/tmp are removed. A folder that fails to load is reported
  /// on stderr and skipped.
  explicit VideoStore(std::filesystem::path root);

  /// Every video's object (see meta()), oldest first.
  std::vector<nlohmann::json> list() const;
  /// The API's Video object: describe_video()'s fields (format, version, intrinsics, fps, frame_count,
  /// amplitude_scale, has_amplitude, has_truth, timestamps_defaulted, source) plus id, name, created
  /// (ISO 8601 UTC), bytes (of the pack), origin ("upload" or "synthetic") and owner (the owner name of
  /// its creator). Throws not_found("video").
  nlohmann::json meta(const std::string& id) const;
  /// The pack file of a video (open a tof::DepthVideoReader on it). Throws not_found("video").
  std::filesystem::path pack_path(const std::string& id) const;
  /// The id of the video called `name`, or "" when none is.
  std::string find_by_name(const std::string& name) const;

  /// Claims an id for a video about to be written. Throws Error(conflict, "video") when the store already
  /// holds (or is writing) limits::kMaxStoredVideos videos.
  std::string reserve();
  /// Gives a reserved id back (a write that failed before commit).
  void release(const std::string& id);
  /// Stores the pack file `file` under the reserved `id`: validated by opening it (tof::DepthVideoReader,
  /// whose errors — 415 not a video, 422 inconsistent, 413 over a limit — pass through with the upload's
  /// temporary name replaced by "the upload") and decoding its first frame; anything that is not a pack
  /// (a bare PNG) is Error(unsupported_format, "body"). `file` is moved into the store (or removed when
  /// refused). The reservation is released on failure. Returns meta().
  nlohmann::json commit_pack(const std::string& id, const std::filesystem::path& file, std::string name,
                             const std::string& owner = "");
  /// Renders a synthetic video (tof::write_synthetic_video) under the reserved `id`, owned by `owner`.
  /// Progress and cancellation as write_synthetic_video (a throw from `progress` leaves nothing behind);
  /// `check` is told the bytes written after each progress report, and a throw from it stops the write the
  /// same way. The reservation is released on failure. Returns meta().
  nlohmann::json commit_synthetic(const std::string& id, const tof::SynthOptions& options, std::string name,
                                  const ProgressFn& progress = {}, const std::string& owner = "",
                                  const WriteCheck& check = {});
  /// Throws not_found("video").
  void remove(const std::string& id);
  std::size_t size() const;

 private:
  nlohmann::json publish(const std::string& id, const std::filesystem::path& tmp, nlohmann::json meta);

  FolderStore folders_;
  mutable std::mutex mu_;          ///< guards pending_ and reserve's count
  std::set<std::string> pending_;  ///< reserved, not yet committed
};

}  // namespace trailscope::server
