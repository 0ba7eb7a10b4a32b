#pragma once
// Everything a route handler may use, built once by `trailscope serve` (or by a test).
#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include "auth/access.hpp"
#include "jobs/disk_budget.hpp"
#include "jobs/job_manager.hpp"
#include "limits.hpp"
#include "routes/router.hpp"
#include "store/bundle_store.hpp"
#include "store/dataset_store.hpp"
#include "store/graph_store.hpp"
#include "store/sector_store.hpp"
#include "jobs/congestion_job.hpp"
#include "store/mot_store.hpp"
#include "store/sweep_store.hpp"
#include "store/run_store.hpp"
#include "store/video_store.hpp"
#include "store/gaze_store.hpp"
#include "replay/replay_manager.hpp"
#include "bundle_stream/bundle_stream_session.hpp"
#include "store/tile_cache.hpp"
#include "store/flow_map_cache.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/density/renderer.hpp"

namespace trailscope::server {

struct App {
  std::shared_ptr<DatasetStore> store;
  std::filesystem::path upload_dir;  ///< where streamed uploads are written
  std::filesystem::path web_root;    ///< built browser app (web/dist); empty = none
  /// limits::kJobWorkers workers; job ids continue across restarts (<data_root>/.last_job_id).
  JobManager jobs;
  /// What jobs may write (jobs/disk_budget.hpp), over the file system of `data_root` (else of the uploads
  /// folder). Tests replace it with a tiny one before they submit.
  std::shared_ptr<DiskBudget> disk;
  TileCache tiles;
  /// Encoded animation chunks (routes/animation.cpp), keyed like the tiles by dataset and creation stamp.
  TileCache animation_chunks{limits::kAnimationCacheBytes};
  density::DensityRenderer density;
  /// The flow maps the flow tiles are drawn from (routes/flow.cpp), computed once per dataset, window and
  /// flow parameters.
  FlowMapCache flow_maps{limits::kFlowMapCacheBytes};
  /// Uploaded graphs and bundling results, opened in `data_root` (null without one: the graph and bundle
  /// routes then answer 500). Declared after `jobs` so they are destroyed first; running jobs hold their
  /// own references.
  std::shared_ptr<GraphStore> graphs;
  std::shared_ptr<BundleStore> bundles;
  /// Depth videos and tracker runs in `data_root` (null without one: their routes then answer 500), and
  /// the live replays over them. Replays are declared last so they stop first.
  std::shared_ptr<VideoStore> videos;
  std::shared_ptr<RunStore> runs;
  /// MOTChallenge text files (POST /api/v1/mot) and parameter sweeps over the runs, in `data_root`.
  std::shared_ptr<MotStore> mot;
  std::shared_ptr<SweepStore> sweeps;
  std::shared_ptr<ReplayManager> replays;
  /// Bundle streams over WebSocket (their worker pool and count); always present.
  std::shared_ptr<BundleStreams> bundle_streams;
  /// Uploaded airspace sectors in `data_root` (null without one: the sector routes then answer 500), and
  /// the results of the last finished congestion jobs (in memory).
  std::shared_ptr<SectorStore> sectors;
  std::shared_ptr<CongestionResults> congestion = std::make_shared<CongestionResults>();
  /// The access check, sessions and sign-in codes over the tokens of <data_root>/tokens.json (in memory
  /// only without a data_root); make_router installs its check. Always present.
  std::shared_ptr<Access> access;
  /// Stored gaze datasets in `data_root` (null without one: the gaze routes then answer 500); leftovers of
  /// interrupted writes are removed at start (the server owns the data folder).
  std::shared_ptr<GazeStore> gaze;

  App(std::shared_ptr<DatasetStore> s, std::filesystem::path uploads, std::filesystem::path web,
      std::size_t tile_cache_bytes, const std::filesystem::path& data_root = {});
};

/// `*part` of the App, or Error(internal, "this server was started without <what>") when the server was
/// started without it (no data folder).
template <typename T>
T& need(const std::shared_ptr<T>& part, const char* what) {
  if (!part) throw Error(Error::Kind::internal, "", std::string("this server was started without ") + what);
  return *part;
}

/// The one table of routes (see proto/openapi.yaml, which lists the same).
Router make_router(App& app);

}  // namespace trailscope::server
