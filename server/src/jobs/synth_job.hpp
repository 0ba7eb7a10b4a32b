#pragma once
// The synth job of POST /api/v1/videos/synth: a synthetic depth video (tof::ToFSynth) written into the
// video store under a reserved id.
#include <memory>
#include <string>

#include "jobs/job_manager.hpp"
#include "store/video_store.hpp"
#include "trailscope/tof/synth.hpp"

namespace trailscope::server {

/// Reserves a video id in `store` (Error(conflict) at limits::kMaxStoredVideos) and queues a job "synth"
/// (JobState::dataset = that id) that writes the video as `name`. The reservation is given back unless
/// the job commits it (also when the job is cancelled while queued, and so never runs). The job's result
/// is the video's meta(). Returns the job and the video id.
std::pair<JobState, std::string> submit_synth(JobManager& jobs, std::shared_ptr<VideoStore> store,
                                              const tof::SynthOptions& options, const std::string& name);

}  // namespace trailscope::server
