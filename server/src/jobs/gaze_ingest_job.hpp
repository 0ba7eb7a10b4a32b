#pragma once
// Ingesting one gaze file into the gaze store (store/gaze_store.hpp): the step `trailscope gaze ingest
// --data-dir` takes, and the job of POST /api/v1/gaze that runs it.
#include <filesystem>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "jobs/disk_budget.hpp"
#include "jobs/job_manager.hpp"
#include "store/gaze_store.hpp"
#include "trailscope/core/progress.hpp"
#include "trailscope/gaze/ingest.hpp"

namespace trailscope::server {

struct GazeIngestRequest {
  std::filesystem::path file;  ///< the gaze file (any format gaze/ingest.hpp reads)
  std::string name;            ///< the dataset id (GazeStore::check_new)
  std::string owner;           ///< "" from the CLI
  /// Format (else detected), geometry overrides, participant and stimulus (gaze::GazeIngestOptions; its
  /// progress and cancel are set here). A recording whose file names no participant gets `name`.
  gaze::GazeIngestOptions options;
};

/// Reads and parses `req.file` (at most limits::kMaxGazeUploadBytes), grants its bytes from `disk` (when
/// given; 507 before anything is written otherwise) and stores it. Progress: parsing 0..0.97, then
/// "store". Returns {"gaze": id, "recordings": N, "samples": N}. Throws check_new's errors (first, before
/// reading), the readers' (415 unsupported_format, 422 unprocessable naming the line, 413), cancelled.
nlohmann::json ingest_gaze_into_store(GazeStore& store, GazeIngestRequest req, const ProgressFn& progress,
                                      const CancelToken* cancel,
                                      const std::shared_ptr<DiskBudget>& disk = nullptr);

/// Queues a job "gaze_ingest" of req.owner (JobState::dataset = the name) running ingest_gaze_into_store,
/// which removes req.file afterwards whatever the outcome (also when cancelled while queued).
JobState submit_gaze_ingest(JobManager& jobs, std::shared_ptr<GazeStore> store, GazeIngestRequest req,
                            std::shared_ptr<DiskBudget> disk = nullptr);

}  // namespace trailscope::server
