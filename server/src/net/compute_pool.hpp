#pragma once
// The compute pool: a few threads that run the handlers of Lane::compute routes (routes/router.hpp), so
// that heavy work never holds a network thread. The threads run at a lower priority (nice) than the
// network threads, and so do the TBB worker threads that join their parallel loops, so that a health
// check or a cached tile is answered while every core computes. The queue is bounded: a request beyond
// it is refused (503) rather than queued behind work that may take minutes.
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "trailscope/core/progress.hpp"

namespace trailscope::server {

class ComputePool {
 public:
  using Task = std::function<void()>;
  /// `workers` >= 1 threads at niceness `nice` (0..19), at most `max_queued` tasks waiting for a thread
  /// (0: a task runs only when a thread is idle).
  ComputePool(unsigned workers, std::size_t max_queued, int nice = 10);
  /// Cancels the tokens of every queued and running task, drops the queued ones and joins the threads (a
  /// running task ends when its compute function next looks at its token).
  ~ComputePool();
  ComputePool(const ComputePool&) = delete;
  ComputePool& operator=(const ComputePool&) = delete;

  /// Queues `task`, which runs on a pool thread unless it is withdrawn first; `token` is the task's
  /// CancelToken (set on shutdown). Returns the task's ticket, or nothing when the queue is full.
  std::optional<std::uint64_t> submit(std::shared_ptr<CancelToken> token, Task task);
  /// Removes the queued task `ticket` (its client left, or its deadline passed); false when it has
  /// already started or ended.
  bool withdraw(std::uint64_t ticket);
  /// Tasks waiting for a thread, and tasks running.
  std::size_t queued() const;
  std::size_t running() const;

 private:
  struct Item {
    std::uint64_t ticket;
    std::shared_ptr<CancelToken> token;
    Task task;
  };
  void work(int nice);
  std::size_t max_queued_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Item> queue_;
  std::vector<std::shared_ptr<CancelToken>> running_;
  std::size_t idle_;  ///< threads not running a task (a queued task is theirs to take)
  std::uint64_t next_ = 1;
  bool stop_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace trailscope::server
