#include "jobs/sweep_job.hpp"

#include "trailscope/core/error.hpp"

namespace trailscope::server {

JobState submit_sweep(JobManager& jobs, std::shared_ptr<RunStore> runs, std::shared_ptr<SweepStore> sweeps,
                      const std::string& sweep, std::vector<tracker::TrackerParams> points,
                      std::vector<tracker::SweepVideo> videos, const tracker::RunOptions& range,
                      const std::string& owner) {
  JobState job;
  try {
    job = jobs.submit(
        "sweep", sweep,
        [runs, sweeps, sweep, points = std::move(points), videos = std::move(videos), range, owner](
            const ProgressFn& progress, const CancelToken& cancel) {
          const auto store_run = [&](tracker::TrackerLog&& log) {
            const nlohmann::json row = runs->put(std::move(log), "sweep", sweep, owner);
            sweeps->add_run(sweep, row.at("id").get<std::string>());
          };
          try {
            tracker::run_sweep(points, videos, range, store_run, progress, &cancel);
          } catch (const Error& e) {
            sweeps->finish(sweep, e.kind() == Error::Kind::cancelled ? "cancelled" : "failed");
            throw;
          } catch (...) {
            sweeps->finish(sweep, "failed");
            throw;
          }
          sweeps->finish(sweep, "done");
          return sweeps->get(sweep);
        },
        owner);
  } catch (...) {
    sweeps->finish(sweep, "failed");  // refused (a quota's 429): the sweep never ran
    throw;
  }
  sweeps->set_job(sweep, job.id);
  return job;
}

}  // namespace trailscope::server
