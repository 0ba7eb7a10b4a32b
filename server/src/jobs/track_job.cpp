#include "jobs/track_job.hpp"

#include "trailscope/tracker/tracker_log.hpp"

namespace trailscope::server {

JobState submit_track(JobManager& jobs, std::shared_ptr<RunStore> runs, std::filesystem::path pack,
                      const tracker::TrackerParams& params, const std::string& video,
                      const std::string& owner) {
  return jobs.submit(
      "track", video,
      [runs, pack, params, video, owner](const ProgressFn& progress, const CancelToken& cancel) {
        tracker::RunOptions ro;
        ro.video_id = video;
        // run_tracker stops at the cancellation's throw; nothing is stored.
        return runs->put(tracker::run_tracker(pack, params, ro, cancellable(progress, cancel)), "track", "",
                         owner);
      },
      owner);
}

}  // namespace trailscope::server
