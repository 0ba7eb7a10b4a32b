#include "net/compute_pool.hpp"

#include <algorithm>
#include <iostream>

#include <sys/resource.h>
#include <unistd.h>

#include <oneapi/tbb/task_scheduler_observer.h>

namespace trailscope::server {

namespace {

// Linux gives each thread its own nice value (setpriority on a thread id); raising it needs no privilege.
void nice_this_thread(int nice) {
  if (nice <= 0) return;
  const int now = getpriority(PRIO_PROCESS, static_cast<id_t>(gettid()));
  if (now < nice) setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), nice);
}

// TBB workers that join a pool thread's parallel loops (its implicit arena) take the pool's niceness: a
// worker thread only ever runs compute tasks, so it may stay niced afterwards.
class NiceObserver : public tbb::task_scheduler_observer {
 public:
  explicit NiceObserver(int nice) : nice_(nice) { observe(true); }
  ~NiceObserver() override { observe(false); }
  void on_scheduler_entry(bool is_worker) override {
    if (is_worker) nice_this_thread(nice_);
  }

 private:
  int nice_;
};

}  // namespace

ComputePool::ComputePool(unsigned workers, std::size_t max_queued, int nice)
    : max_queued_(max_queued), idle_(std::max(1u, workers)) {
  for (unsigned i = 0; i < std::max(1u, workers); ++i) threads_.emplace_back([this, nice] { work(nice); });
}

ComputePool::~ComputePool() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
    for (auto& item : queue_) item.token->cancel();
    queue_.clear();
    for (auto& t : running_) t->cancel();
  }
  wake_.notify_all();
  for (auto& t : threads_) t.join();
}

std::optional<std::uint64_t> ComputePool::submit(std::shared_ptr<CancelToken> token, Task task) {
  std::uint64_t ticket;
  {
    std::lock_guard lock(mutex_);
    // Tasks an idle thread is about to take do not wait: the queue limit counts the others.
    if (stop_ || queue_.size() >= max_queued_ + idle_) return std::nullopt;
    ticket = next_++;
    queue_.push_back({ticket, std::move(token), std::move(task)});
  }
  wake_.notify_one();
  return ticket;
}

bool ComputePool::withdraw(std::uint64_t ticket) {
  std::lock_guard lock(mutex_);
  auto it = std::find_if(queue_.begin(), queue_.end(), [&](const Item& i) { return i.ticket == ticket; });
  if (it == queue_.end()) return false;
  queue_.erase(it);
  return true;
}

std::size_t ComputePool::queued() const {
  std::lock_guard lock(mutex_);
  return queue_.size() > idle_ ? queue_.size() - idle_ : 0;
}

std::size_t ComputePool::running() const {
  std::lock_guard lock(mutex_);
  return running_.size();
}

void ComputePool::work(int nice) {
  nice_this_thread(nice);
  NiceObserver observer(nice);
  for (;;) {
    Item item;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || !queue_.empty(); });
      if (stop_) return;
      item = std::move(queue_.front());
      queue_.pop_front();
      --idle_;
      running_.push_back(item.token);
    }
    try {
      item.task();
    } catch (const std::exception& e) {  // tasks answer their own errors; this is a bug
      std::cerr << "compute task failed: " << e.what() << "\n";
    }
    std::lock_guard lock(mutex_);
    running_.erase(std::find(running_.begin(), running_.end(), item.token));
    ++idle_;
  }
}

}  // namespace trailscope::server
