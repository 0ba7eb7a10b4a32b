#pragma once
// The bundle job: one bundling, from its source to a StoredBundle, the same steps for POST /api/v1/bundles
// (submit_bundle) and for `trailscope bundle` (run_bundle). A source is the flight trails of a dataset
// under a window query, or a graph.
#include <limits>
#include <map>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "store/bundle_store.hpp"
#include "jobs/disk_budget.hpp"
#include "jobs/job_manager.hpp"
#include "store/dataset_store.hpp"
#include "store/graph_store.hpp"
#include "trailscope/bundling/graph_io.hpp"
#include "trailscope/bundling/params.hpp"
#include "trailscope/core/backend.hpp"
#include "trailscope/core/progress.hpp"

namespace trailscope::server {

/// The input of a bundling in bundle pixels, with where it came from.
struct BundleInput {
  bundling::Polylines px;
  bundling::Frame frame;
  BundleUnits units = BundleUnits::plane;
  nlohmann::json source;
  std::string dataset;  ///< the dataset of flight trails, else ""
  std::uint64_t input_points = 0;
};

/// The flight trails of `ds` under `query`, split at gaps over `max_gap` s, in the pixels of the query's
/// view (its bbox, else the matching points' extent). Throws what parse_query and flight_trails throw.
BundleInput input_from_dataset(const Dataset& ds, const std::map<std::string, std::string>& query,
                               double max_gap, const bundling::BundleParams& params);
/// A graph fitted into the bundle image (Frame::fit with params.border; y flipped when the graph's y
/// grows upward). `source` is what the result records as its source.
BundleInput input_from_graph(const bundling::Graph& g, const bundling::BundleParams& params,
                             nlohmann::json source);

/// Bundles `in` and returns the result as bundle `id` (not stored). The geometry is rounded to float32,
/// as the store keeps it, so a result draws the same before and after a restart.
std::shared_ptr<StoredBundle> run_bundle(BundleInput in, const std::string& id,
                                         const bundling::BundleParams& params, Backend backend,
                                         const ProgressFn& progress, const CancelToken* cancel);

/// Queues a job "bundle" of `owner` (JobState::dataset = `source`, the dataset or graph id) that bundles
/// `in` as bundle `id` (BundleStore::reserve_id) and puts it into `store`, once `disk` (when given) has
/// granted its bytes (BundleStore::bytes_estimate; the job fails with 507 and the numbers otherwise); the
/// job's result is the bundle's JSON.
JobState submit_bundle(JobManager& jobs, std::shared_ptr<BundleStore> store, BundleInput in, std::string id,
                       const bundling::BundleParams& params, Backend backend, std::string source,
                       std::shared_ptr<DiskBudget> disk = nullptr, const std::string& owner = "");

}  // namespace trailscope::server
