#pragma once
// Progress reporting and cooperative cancellation for long operations (ingest, bundling, sweeps).
#include <atomic>
#include <functional>
#include <string_view>

#include "trailscope/core/error.hpp"

namespace trailscope {

/// Called with the fraction done in [0, 1] and a short stage name ("parse", "assemble", ...).
/// Implementations must be cheap: callers report at most every few thousand rows.
using ProgressFn = std::function<void(double fraction, std::string_view stage)>;

/// Set from another thread to ask a running operation to stop; the operation throws
/// Error(Kind::cancelled) at its next check and leaves no partial result behind.
class CancelToken {
 public:
  void cancel() noexcept { flag_.store(true, std::memory_order_relaxed); }
  bool cancelled() const noexcept { return flag_.load(std::memory_order_relaxed); }
  void throw_if_cancelled() const {
    if (cancelled()) throw Error(Error::Kind::cancelled, "", "operation cancelled");
  }

 private:
  std::atomic<bool> flag_{false};
};

}  // namespace trailscope
