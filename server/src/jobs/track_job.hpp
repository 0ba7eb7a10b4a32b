#pragma once
// The track job of POST /api/v1/runs/track: the tracker over one stored video (tracker::run_tracker),
// its log into the run store.
#include <filesystem>
#include <memory>
#include <string>

#include "jobs/job_manager.hpp"
#include "store/run_store.hpp"
#include "trailscope/tracker/params.hpp"

namespace trailscope::server {

/// Queues a job "track" of `owner` (JobState::dataset = `video`) that tracks the video file `pack` with
/// `params` and puts the log into `runs` (source "track"); a cancelled run stores nothing. The job's result
/// is the run's row.
JobState submit_track(JobManager& jobs, std::shared_ptr<RunStore> runs, std::filesystem::path pack,
                      const tracker::TrackerParams& params, const std::string& video,
                      const std::string& owner = "");

}  // namespace trailscope::server
