#pragma once
// Everything a route handler may use, built once by `trailscope serve` (or by a test).
#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include "jobs/job_manager.hpp"
#include "routes/router.hpp"
#include "store/bundle_store.hpp"
#include "store/dataset_store.hpp"
#include "store/graph_store.hpp"
#include "store/tile_cache.hpp"
#include "trailscope/density/renderer.hpp"

namespace trailscope::server {

struct App {
  std::shared_ptr<DatasetStore> store;
  std::filesystem::path upload_dir;  ///< where streamed uploads are written
  std::filesystem::path web_root;    ///< built browser app (web/dist); empty = none
  JobManager jobs{1};
  TileCache tiles;
  density::DensityRenderer density;
  /// Uploaded graphs and bundling results, opened in `data_root` (null without one: the graph and bundle
  /// routes then answer 500). Declared after `jobs` so they are destroyed first; running jobs hold their
  /// own references.
  std::shared_ptr<GraphStore> graphs;
  std::shared_ptr<BundleStore> bundles;

  App(std::shared_ptr<DatasetStore> s, std::filesystem::path uploads, std::filesystem::path web,
      std::size_t tile_cache_bytes, const std::filesystem::path& data_root = {});
};

/// The one table of routes (see proto/openapi.yaml, which lists the same).
Router make_router(App& app);

}  // namespace trailscope::server
