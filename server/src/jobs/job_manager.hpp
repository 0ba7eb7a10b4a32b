#pragma once
// Long operations (ingest, bundling, synthetic videos, tracker runs and sweeps: one file per kind in
// jobs/) run as jobs on a few worker threads (limits::kJobWorkers: a short ingest does not wait behind a
// long synth). A job reports progress through a ProgressFn and can be cancelled; every change of a job is
// announced to listeners (the WebSocket hub), throttled so that a fast job does not flood slow clients.
// Admission: one owner has at most limits::kMaxQueuedJobsPerOwner jobs queued or running (one more is a
// 429 with Retry-After); job ids are never reused, not even after a restart (the high-water mark is
// persisted, store/id_counter.hpp). What a job may write is checked by jobs/disk_budget.hpp.
#include <chrono>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "store/id_counter.hpp"
#include "trailscope/core/progress.hpp"

namespace trailscope::server {

struct JobState {
  std::string id;       ///< "j1", "j2", ...
  std::string kind;     ///< "ingest", "bundle", "synth", "track", "sweep"
  std::string state;    ///< queued | running | done | failed | cancelled
  double progress = 0;  ///< [0, 1]
  std::string stage;
  std::string dataset;  ///< the dataset the job creates or reads (a bundle job: its source, dataset or graph)
  std::string owner;    ///< the owner name of its submitter ("" from the CLI); it or an admin may cancel
  nlohmann::json result;  ///< on done
  nlohmann::json error;   ///< the error body {"error","detail","param"} on failed (errors/error_table.hpp)
  nlohmann::json to_json() const;
};

class JobManager {
 public:
  /// The work: reports progress, checks the token, returns the result JSON or throws.
  using Work = std::function<nlohmann::json(const ProgressFn&, const CancelToken&)>;
  using Listener = std::function<void(const JobState&)>;

  /// Starts `workers` worker threads (at least 1). `id_file` keeps the high-water mark of job ids
  /// (IdCounter; empty: in memory only, numbering from j1). Throws as IdCounter.
  explicit JobManager(unsigned workers = 1, std::filesystem::path id_file = {});
  ~JobManager();  ///< cancels running jobs and joins the workers

  /// Queues a job of `owner` and returns its state right away. Throws check_quota's 429.
  JobState submit(std::string kind, std::string dataset, Work work, std::string owner = "");
  /// Throws RetryLater(too_many_requests, "job") with Retry-After limits::kJobRetryAfterSeconds when
  /// `owner` has limits::kMaxQueuedJobsPerOwner jobs queued or running. submit() checks it too; a handler
  /// that creates something before submitting checks first.
  void check_quota(const std::string& owner) const;
  /// Throws not_found("job").
  JobState get(const std::string& id) const;
  std::vector<JobState> list() const;
  /// Asks a queued or running job to stop; throws not_found("job").
  JobState cancel(const std::string& id);
  /// Blocks until the job has ended (tests and the CLI).
  JobState wait(const std::string& id);
  void add_listener(Listener l);

 private:
  struct Job {
    JobState state;
    Work work;
    CancelToken cancel;
    std::chrono::steady_clock::time_point last_event{};
  };
  void worker_loop();
  void notify(const JobState& s);
  void check_quota_locked(const std::string& owner) const;

  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::map<std::string, std::shared_ptr<Job>> jobs_;
  std::deque<std::shared_ptr<Job>> queue_;
  std::deque<std::string>
      finished_;  ///< ids of ended jobs, oldest first (pruned past limits::kMaxFinishedJobs)
  std::vector<Listener> listeners_;
  std::vector<std::thread> workers_;
  IdCounter ids_;
  bool stopping_ = false;
};

/// `progress` preceded by a cancellation check: the returned function throws Error(cancelled) once
/// `cancel` is set, so a compute/ function that reports progress stops at its next report and what it
/// was building is dropped. Both must outlive the returned function.
ProgressFn cancellable(const ProgressFn& progress, const CancelToken& cancel);

}  // namespace trailscope::server
