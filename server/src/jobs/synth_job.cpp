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

std::uint64_t synth_bytes_estimate(const tof::SynthOptions& o) {
  return static_cast<std::uint64_t>(o.frames) * static_cast<std::uint64_t>(o.width) *
         static_cast<std::uint64_t>(o.height) * kSynthBytesPerPixel;
}

std::pair<JobState, std::string> submit_synth(JobManager& jobs, std::shared_ptr<VideoStore> store,
                                              const tof::SynthOptions& options, const std::string& name,
                                              DiskBudget& disk, const std::string& owner) {
  jobs.check_quota(owner);  // before the grant and the id: a refused job holds neither
  const std::shared_ptr<const DiskBudget::Grant> grant = disk.admit(
      synth_bytes_estimate(options), "frames", "the video",
      std::to_string(options.frames) + " frames × " + std::to_string(options.width) + " × " +
          std::to_string(options.height) + " px × " + std::to_string(kSynthBytesPerPixel) + " bytes");
  // Built in place: a copy's destructor would give the id back at once.
  const std::shared_ptr<Reservation> reservation(new Reservation{store, store->reserve()});
  const std::string id = reservation->id;
  const JobState job = jobs.submit(
      "synth", id,
      [reservation, grant, options, name, owner](const ProgressFn& progress, const CancelToken& cancel) {
        // The writer removes its temporary file on the way out of a cancellation or a stop.
        return reservation->store->commit_synthetic(
            reservation->id, options, name, cancellable(progress, cancel), owner,
            [&grant](std::uint64_t written) { grant->check(written); });
      },
      owner);
  return {job, id};
}

}  // namespace trailscope::server
