#pragma once
// The synth job of POST /api/v1/videos/synth: a synthetic depth video (tof::ToFSynth) written into the
// video store under a reserved id.
#include <memory>
#include <string>

#include "jobs/disk_budget.hpp"
#include "jobs/job_manager.hpp"
#include "store/video_store.hpp"
#include "trailscope/tof/synth.hpp"

namespace trailscope::server {

/// Bytes per pixel of a frame as the video store writes it: 16-bit depth and 16-bit amplitude, before the
/// PNG compression (which noise defeats: a noisy 1024 × 1024 frame packs to 1.6 MB of the 4 MB).
inline constexpr std::uint64_t kSynthBytesPerPixel = 4;
/// The bytes a synthetic video may take: frames × width × height × kSynthBytesPerPixel.
std::uint64_t synth_bytes_estimate(const tof::SynthOptions& options);

/// Grants the video's estimated bytes from `disk` (Error(insufficient_storage, "frames") with the numbers
/// when over the budget), reserves a video id in `store` (Error(conflict) at limits::kMaxStoredVideos) and
/// queues a job "synth" of `owner` (JobState::dataset = that id) that writes the video as `name`, checking
/// what it has written against the grant after every batch of frames (a stop leaves nothing). The
/// reservation and the grant are given back when the job ends (also when it is cancelled while queued,
/// and so never runs). The job's result is the video's meta(). Returns the job and the video id.
std::pair<JobState, std::string> submit_synth(JobManager& jobs, std::shared_ptr<VideoStore> store,
                                              const tof::SynthOptions& options, const std::string& name,
                                              DiskBudget& disk, const std::string& owner = "");

}  // namespace trailscope::server
