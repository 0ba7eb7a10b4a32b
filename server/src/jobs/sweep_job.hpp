#pragma once
// The sweep job of POST /api/v1/sweeps: the tracker at every point of a parameter sweep on every video
// (tracker::run_sweep); each run goes to the run store tagged with the sweep's id, and the sweep store
// records the runs and how the sweep ended.
#include <memory>
#include <string>
#include <vector>

#include "jobs/job_manager.hpp"
#include "store/run_store.hpp"
#include "store/sweep_store.hpp"
#include "trailscope/tracker/sweep.hpp"

namespace trailscope::server {

/// Queues a job "sweep" of `owner`, whose runs it owns too (JobState::dataset = `sweep`, an id of
/// SweepStore::create) over `points` x `videos` on the frames of `range` (first_frame, frame_count). On any
/// end the sweep is finished as "done", "cancelled" or "failed"; the job's result is the sweep's JSON.
/// Records the job on the sweep.
JobState submit_sweep(JobManager& jobs, std::shared_ptr<RunStore> runs, std::shared_ptr<SweepStore> sweeps,
                      const std::string& sweep, std::vector<tracker::TrackerParams> points,
                      std::vector<tracker::SweepVideo> videos, const tracker::RunOptions& range,
                      const std::string& owner = "");

}  // namespace trailscope::server
