#include "jobs/bundle_job.hpp"

#include <cmath>

#include "store/dataset_ingest.hpp"
#include "trailscope/bundling/bundle.hpp"
#include "trailscope/bundling/flight_trails.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/trails/query.hpp"

namespace trailscope::server {

namespace {
void round_to_float(std::vector<double>& v) {
  for (double& x : v) x = static_cast<float>(x);
}
}  // namespace

BundleInput input_from_dataset(const Dataset& ds, const std::map<std::string, std::string>& query,
                               double max_gap, const bundling::BundleParams& params) {
  const Query q = parse_query(query);
  bundling::FlightTrails ft = bundling::flight_trails(*ds.trails, q, params.size, max_gap);
  BundleInput in;
  in.px = ft.frame.to_pixels(ft.lines);
  in.frame = ft.frame;
  in.units = BundleUnits::merc32;
  in.dataset = ds.id;
  in.input_points = ft.lines.points();
  nlohmann::json qj = nlohmann::json::object();
  for (const auto& [k, v] : query) qj[k] = v;
  in.source = {{"dataset", ds.id},
               {"query", qj},
               {"canonical", q.canonical()},
               {"max_gap", std::isinf(max_gap) ? nlohmann::json(nullptr) : nlohmann::json(max_gap)},
               {"trails", ft.lines.size()}};
  return in;
}

BundleInput input_from_graph(const bundling::Graph& g, const bundling::BundleParams& params,
                             nlohmann::json source) {
  BundleInput in;
  // A graph has no view: it is fitted into the image with a border (CUBu's normalisation), drawn with
  // y up when its coordinates grow upward (geographic graphs), so the picture is not upside down.
  in.frame = bundling::Frame::fit(g.edges, params.size, params.border, g.y_up);
  in.px = in.frame.to_pixels(g.edges);
  in.units = g.geographic ? BundleUnits::epsg3857 : BundleUnits::plane;
  in.input_points = g.edges.points();
  in.source = std::move(source);
  return in;
}

std::shared_ptr<StoredBundle> run_bundle(BundleInput in, const std::string& id,
                                         const bundling::BundleParams& params, Backend backend,
                                         const ProgressFn& progress, const CancelToken* cancel) {
  auto sb = std::make_shared<StoredBundle>();
  sb->bundled = bundling::bundle(in.px, in.frame, params, backend, progress, cancel);
  if (cancel) cancel->throw_if_cancelled();
  bundling::Bundled& b = sb->bundled;
  for (auto* v : {&b.lines.x, &b.lines.y, &b.original.x, &b.original.y}) round_to_float(*v);
  sb->id = id;
  sb->created = utc_now_iso();
  sb->source = std::move(in.source);
  sb->dataset = std::move(in.dataset);
  sb->units = in.units;
  sb->input_points = in.input_points;
  return sb;
}

JobState submit_bundle(JobManager& jobs, std::shared_ptr<BundleStore> store, BundleInput in, std::string id,
                       const bundling::BundleParams& params, Backend backend, std::string source,
                       std::shared_ptr<DiskBudget> disk, const std::string& owner) {
  auto input = std::make_shared<BundleInput>(std::move(in));
  return jobs.submit(
      "bundle", std::move(source),
      [store, input, id, params, backend, disk, owner](const ProgressFn& progress,
                                                       const CancelToken& cancel) {
        const auto sb = run_bundle(std::move(*input), id, params, backend, progress, &cancel);
        sb->owner = owner;
        std::shared_ptr<const DiskBudget::Grant> grant;  // held until the bundle is written
        if (disk)
          grant = disk->admit(BundleStore::bytes_estimate(*sb), "bundle", "the bundle",
                              std::to_string(sb->bundled.lines.points()) + " points × " +
                                  std::to_string(BundleStore::kBytesPerPoint) + " bytes and " +
                                  std::to_string(sb->bundled.lines.size()) + " polylines × " +
                                  std::to_string(BundleStore::kBytesPerPolyline) + " bytes");
        // Bundles evicted beyond kMaxStoredBundles keep their cached tiles until the LRU
        // drops them: their keys can never be asked for again.
        store->put(sb);
        return sb->to_json();
      },
      owner);
}

}  // namespace trailscope::server
