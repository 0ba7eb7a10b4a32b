#pragma once
// Stored gaze datasets: the ingested recordings of one uploaded gaze file, kept like a flight dataset
// (embedded_store.hpp) under <root>/gaze/<id>/, the id being the name the uploader chose ([a-z0-9_-],
// 1..64, validate_dataset_id). A dataset folder holds recordings.tsgz (store/gaze_file.hpp,
// proto/gaze_store.md) and manifest.json, written last; it is written into <root>/tmp/gaze.<id>.<random>/
// and renamed into place (stage_folder / publish_folder, folder_store.hpp), so after a crash it is there
// whole or not at all, and deleted by renaming it into tmp/ first (remove_folder). Opening with
// Leftovers::remove clears what tmp/ holds of gaze datasets (the server does; a CLI verb beside a running
// server must not). Every manifest stays in memory (listing reads no samples); the recordings of the
// last few datasets used stay loaded. Stimulus images uploaded for a dataset live in its folder,
// stimuli/<hex BLAKE2b-128 of the stimulus name>.png|.jpg, each written atomically before the manifest
// that names it is replaced atomically. At most limits::kMaxStoredGazeDatasets datasets (409 beyond).
// Thread-safe.
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "store/folder_store.hpp"
#include "trailscope/gaze/gaze.hpp"
#include "trailscope/gaze/stimulus.hpp"

namespace trailscope::server {

class GazeStore {
 public:
  enum class Leftovers { keep, remove };
  /// Opens (creating if needed) <root>/gaze and <root>/tmp, clears gaze leftovers in tmp/ when asked, and
  /// notes every complete dataset (its manifest). A folder whose manifest is unreadable is reported on
  /// stderr and skipped, never deleted. Throws Error(internal) when a folder cannot be created.
  explicit GazeStore(std::filesystem::path root, Leftovers leftovers = Leftovers::keep);

  /// Every dataset's summary (the API's GazeDataset object without its recording_list), by id.
  std::vector<nlohmann::json> list() const;
  /// One dataset's object with "recording_list" (index, participant, stimulus, trial, format, units,
  /// rate_hz, samples, valid_samples, t0_ms, t1_ms, geometry, tracker_events, annotations) and
  /// "stimulus_images". Throws not_found("gaze").
  nlohmann::json meta(const std::string& id) const;
  bool contains(const std::string& id) const;
  std::size_t size() const;
  /// The owner name of `id`. Throws not_found("gaze").
  std::string owner(const std::string& id) const;
  /// The recordings, read from disk when not loaded. Throws not_found("gaze"); Error(internal) when the
  /// file is damaged (decode_gaze_file's message).
  std::shared_ptr<const gaze::GazeDataset> get(const std::string& id) const;

  /// Throws invalid_argument("name") for a malformed id, Error(conflict, "name") when it is taken or the
  /// store holds limits::kMaxStoredGazeDatasets datasets: what an upload checks before its body is read.
  void check_new(const std::string& id) const;
  /// Stores `ds` as `id` whole or not at all (check_new's errors, again under the lock) and returns its
  /// object (meta()). `format` is the detected or given format name.
  nlohmann::json put(const std::string& id, const std::string& owner, const std::string& format,
                     std::shared_ptr<const gaze::GazeDataset> ds);
  /// Throws not_found("gaze").
  void remove(const std::string& id);

  /// Stores the image of stimulus `stimulus` of dataset `id` (replacing an earlier one). `image` is
  /// checked by the caller (gaze::inspect_stimulus_image). Throws not_found("gaze"),
  /// invalid_argument("stimulus") when no recording of the dataset has that stimulus.
  nlohmann::json put_stimulus(const std::string& id, const std::string& stimulus, const std::string& bytes,
                              const gaze::StimulusImage& image);
  struct Image {
    std::string bytes, content_type;
  };
  /// The image of `stimulus`. Throws not_found("gaze"), not_found("stimulus") when none was uploaded.
  Image stimulus(const std::string& id, const std::string& stimulus) const;

  /// Bytes a dataset takes on disk (its file plus 64 KiB of manifest): what a disk budget grants.
  static std::uint64_t bytes_estimate(const gaze::GazeDataset& ds);

 private:
  std::filesystem::path dir(const std::string& id) const { return root_ / "gaze" / id; }
  const nlohmann::json& manifest_locked(const std::string& id) const;

  std::filesystem::path root_;
  mutable std::mutex mu_;
  std::map<std::string, nlohmann::json> manifests_;  ///< id -> manifest (magic and version removed)
  mutable RecentItems<gaze::GazeDataset> loaded_;
};

/// The summary of a gaze dataset (the list's object) from its manifest.
nlohmann::json gaze_summary(const nlohmann::json& manifest);

}  // namespace trailscope::server
