#include "jobs/job_manager.hpp"

#include <algorithm>

#include "errors/error_table.hpp"
#include "store/failpoint.hpp"
#include "trailscope/core/error.hpp"
#include "limits.hpp"

namespace trailscope::server {

namespace {
// A progress event is sent at most this often per job (the final state always is).
constexpr auto kProgressInterval = std::chrono::milliseconds(100);
}  // namespace

ProgressFn cancellable(const ProgressFn& progress, const CancelToken& cancel) {
  return [&progress, &cancel](double fraction, std::string_view stage) {
    cancel.throw_if_cancelled();
    progress(fraction, stage);
  };
}

nlohmann::json JobState::to_json() const {
  return {{"id", id},       {"kind", kind},       {"state", state},   {"progress", progress},
          {"stage", stage}, {"dataset", dataset}, {"result", result}, {"error", error},
          {"owner", owner}};
}

JobManager::JobManager(unsigned workers, std::filesystem::path id_file) : ids_(std::move(id_file)) {
  for (unsigned i = 0; i < std::max(1u, workers); ++i) workers_.emplace_back([this] { worker_loop(); });
}

JobManager::~JobManager() {
  {
    std::lock_guard lock(mu_);
    stopping_ = true;
    for (auto& [id, job] : jobs_) job->cancel.cancel();
  }
  cv_.notify_all();
  for (auto& t : workers_) t.join();
}

void JobManager::check_quota_locked(const std::string& owner) const {
  std::size_t active = 0;
  for (const auto& [id, job] : jobs_)
    active += job->state.owner == owner && (job->state.state == "queued" || job->state.state == "running");
  if (active >= limits::kMaxQueuedJobsPerOwner)
    throw RetryLater(
        Error::Kind::too_many_requests, "job",
        "owner '" + owner + "' has " + std::to_string(active) + " jobs queued or running, the most " +
            "one owner may have (kMaxQueuedJobsPerOwner = " + std::to_string(limits::kMaxQueuedJobsPerOwner) +
            "); retry when one has ended, or cancel one",
        limits::kJobRetryAfterSeconds);
}

void JobManager::check_quota(const std::string& owner) const {
  std::lock_guard lock(mu_);
  check_quota_locked(owner);
}

JobState JobManager::submit(std::string kind, std::string dataset, Work work, std::string owner) {
  auto job = std::make_shared<Job>();
  JobState s;
  {
    std::lock_guard lock(mu_);
    check_quota_locked(owner);
    // Persisted before it is handed out (IdCounter): a 202 naming this id never names another job later.
    job->state.id = "j" + std::to_string(ids_.next());
    job->state.owner = std::move(owner);
    job->state.kind = std::move(kind);
    job->state.state = "queued";
    job->state.dataset = std::move(dataset);
    job->work = std::move(work);
    jobs_[job->state.id] = job;
    s = job->state;
  }
  // Announce "queued" before a worker can see the job, so listeners never get "running" first.
  notify(s);
  {
    std::lock_guard lock(mu_);
    queue_.push_back(job);
  }
  cv_.notify_all();
  return s;
}

JobState JobManager::get(const std::string& id) const {
  std::lock_guard lock(mu_);
  auto it = jobs_.find(id);
  if (it == jobs_.end()) throw not_found("job", "job '" + id + "' does not exist");
  return it->second->state;
}

std::vector<JobState> JobManager::list() const {
  std::lock_guard lock(mu_);
  std::vector<JobState> out;
  for (const auto& [id, job] : jobs_) out.push_back(job->state);
  return out;
}

JobState JobManager::cancel(const std::string& id) {
  JobState s;
  {
    std::lock_guard lock(mu_);
    auto it = jobs_.find(id);
    if (it == jobs_.end()) throw not_found("job", "job '" + id + "' does not exist");
    it->second->cancel.cancel();
    s = it->second->state;
  }
  cv_.notify_all();
  return s;
}

JobState JobManager::wait(const std::string& id) {
  std::unique_lock lock(mu_);
  auto it = jobs_.find(id);
  if (it == jobs_.end()) throw not_found("job", "job '" + id + "' does not exist");
  auto job = it->second;
  cv_.wait(lock, [&] {
    const auto& st = job->state.state;
    return st == "done" || st == "failed" || st == "cancelled";
  });
  return job->state;
}

void JobManager::add_listener(Listener l) {
  std::lock_guard lock(mu_);
  listeners_.push_back(std::move(l));
}

void JobManager::notify(const JobState& s) {
  std::vector<Listener> ls;
  {
    std::lock_guard lock(mu_);
    ls = listeners_;
  }
  for (auto& l : ls) l(s);
}

void JobManager::worker_loop() {
  for (;;) {
    std::shared_ptr<Job> job;
    {
      std::unique_lock lock(mu_);
      cv_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
      if (stopping_) return;
      job = queue_.front();
      queue_.pop_front();
      job->state.state = job->cancel.cancelled() ? "cancelled" : "running";
    }
    if (job->state.state == "cancelled") {
      job->work = nullptr;  // never runs: release what it captured (upload files, reservations) now
      {
        std::lock_guard lock(mu_);
        finished_.push_back(job->state.id);
      }
      notify(job->state);
      cv_.notify_all();
      continue;
    }
    notify(job->state);
    const ProgressFn progress = [&](double fraction, std::string_view stage) {
      failpoint("job.progress", job->state.kind);
      JobState snapshot;
      {
        std::lock_guard lock(mu_);
        job->state.progress = std::clamp(fraction, 0.0, 1.0);
        job->state.stage = std::string(stage);
        const auto now = std::chrono::steady_clock::now();
        if (now - job->last_event < kProgressInterval) return;
        job->last_event = now;
        snapshot = job->state;
      }
      notify(snapshot);
    };
    JobState final_state;
    try {
      nlohmann::json result = job->work(progress, job->cancel);
      std::lock_guard lock(mu_);
      job->state.state = "done", job->state.progress = 1.0, job->state.result = std::move(result);
      final_state = job->state;
    } catch (const Error& e) {
      std::lock_guard lock(mu_);
      job->state.state = e.kind() == Error::Kind::cancelled ? "cancelled" : "failed";
      if (job->state.state == "failed") job->state.error = error_body(e).body;
      final_state = job->state;
    } catch (const std::exception& e) {
      std::lock_guard lock(mu_);
      job->state.state = "failed";
      job->state.error = error_body(e).body;
      final_state = job->state;
    }
    job->work = nullptr;  // release captured resources (upload files, data) early
    {
      std::lock_guard lock(mu_);
      finished_.push_back(job->state.id);
      while (finished_.size() > limits::kMaxFinishedJobs) {
        jobs_.erase(finished_.front());
        finished_.pop_front();
      }
    }
    cv_.notify_all();
    notify(final_state);
  }
}

}  // namespace trailscope::server
