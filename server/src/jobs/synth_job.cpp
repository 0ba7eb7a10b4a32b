#include "jobs/synth_job.hpp"

namespace trailscope::server {

namespace {
/// Gives a reserved video id back unless the job committed it (a job cancelled while queued never runs).
struct Reservation {
  std::shared_ptr<VideoStore> store;
  std::string id;
  ~Reservation() { store->release(id); }
};
}  // namespace

std::pair<JobState, std::string> submit_synth(JobManager& jobs, std::shared_ptr<VideoStore> store,
                                              const tof::SynthOptions& options, const std::string& name) {
  // Built in place: a copy's destructor would give the id back at once.
  const std::shared_ptr<Reservation> reservation(new Reservation{store, store->reserve()});
  const std::string id = reservation->id;
  const JobState job = jobs.submit(
      "synth", id, [reservation, options, name](const ProgressFn& progress, const CancelToken& cancel) {
        // The writer removes its temporary file on the way out of a cancellation.
        return reservation->store->commit_synthetic(reservation->id, options, name,
                                                    cancellable(progress, cancel));
      });
  return {job, id};
}

}  // namespace trailscope::server
