#pragma once
// The congestion job: occupancy and entry counts, hotspots, complexity (congestion/counts.hpp) and
// losses of separation (congestion/separation.hpp) of one dataset window, the same steps for
// POST /api/v1/congestion (submit_congestion) and for `trailscope congestion` (run_congestion). The
// result is kept in memory, the last limits::kMaxCongestionResults of them (CongestionResults), and served
// by GET /api/v1/congestion/{job} as JSON or CSV; the job's own result is a summary of it.
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "jobs/job_manager.hpp"
#include "params/congestion_body.hpp"
#include "store/dataset_store.hpp"
#include "trailscope/congestion/counts.hpp"
#include "trailscope/congestion/separation.hpp"
#include "trailscope/core/progress.hpp"

namespace trailscope::server {

/// What one congestion request computed.
struct CongestionOutput {
  std::string dataset;
  std::string sectors;     ///< the sector set (API: its id; CLI: the file), "" for the grid
  nlohmann::json volumes;  ///< the request's volumes object
  std::vector<std::string> compute;
  std::optional<congestion::CountsResult> counts;          ///< when any count was asked for
  std::optional<congestion::SeparationResult> separation;  ///< when separation was asked for

  /// {"dataset","volumes","compute","counts": CountsResult::to_json() | null,
  ///  "separation": SeparationResult::to_json() | null}; the parts compute leaves out are empty in
  /// `counts` (no occupancy or entries series, no hotspots, complexity null).
  nlohmann::json to_json() const;
  /// One table as CSV: "series" (occupancy and entry counts, CountsResult::write_csv), "hotspots",
  /// "complexity" or "separation" (SeparationResult::to_csv). Throws invalid_argument("table") for
  /// another name or a table compute did not ask for.
  std::string csv(const std::string& table) const;
  /// The job's result: {"congestion": "/api/v1/congestion/<job>" (set by the caller), "dataset",
  /// "compute", "flights", "volumes", "steps", "hotspots" (all found), "separation_events"}.
  nlohmann::json summary() const;
};

/// The tables csv() knows, in order.
const std::vector<std::string>& congestion_tables();

/// Computes what `r` asks on `set` (r.counts.sectors already loaded when r.sectors is set). Progress:
/// the counts' stages ("inside", "counts", "complexity"), then "separation", monotonic over [0, 1].
/// Throws what congestion::count() and losses_of_separation() throw (Error(cancelled) when `cancel` is
/// set).
std::shared_ptr<CongestionOutput> run_congestion(const TrailSet& set, const CongestionRequest& r,
                                                 const ProgressFn& progress, const CancelToken* cancel);

/// The results of the last limits::kMaxCongestionResults finished congestion jobs, by job id (the oldest
/// is dropped when one more arrives). Thread-safe.
class CongestionResults {
 public:
  void put(const std::string& job, std::shared_ptr<const CongestionOutput> out);
  /// The result of `job`, or null when it has none (yet, or any more).
  std::shared_ptr<const CongestionOutput> get(const std::string& job) const;

 private:
  mutable std::mutex mu_;
  std::map<std::string, std::shared_ptr<const CongestionOutput>> results_;
  std::deque<std::string> order_;  ///< oldest first
};

/// Queues a job "congestion" (JobState::dataset = the dataset's id) that runs `r` on `ds` and puts the
/// output into `results` under the job's id; the job's result is CongestionOutput::summary().
JobState submit_congestion(JobManager& jobs, std::shared_ptr<CongestionResults> results,
                           std::shared_ptr<const Dataset> ds, CongestionRequest r,
                           const std::string& owner = "");

}  // namespace trailscope::server
