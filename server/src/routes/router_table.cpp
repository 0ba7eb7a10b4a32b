#include "routes/app.hpp"
#include "routes/collection.hpp"
#include "routes/handlers.hpp"
#include "limits.hpp"

namespace trailscope::server {

App::App(std::shared_ptr<DatasetStore> s, std::filesystem::path uploads, std::filesystem::path web,
         std::size_t tile_cache_bytes, const std::filesystem::path& data_root)
    : store(std::move(s)),
      upload_dir(std::move(uploads)),
      web_root(std::move(web)),
      jobs(limits::kJobWorkers, data_root.empty() ? data_root : data_root / ".last_job_id"),
      disk(DiskBudget::open(data_root.empty() ? upload_dir : data_root)),
      tiles(tile_cache_bytes) {
  if (!data_root.empty()) {
    graphs = std::make_shared<GraphStore>(data_root);
    bundles = std::make_shared<BundleStore>(data_root);
    videos = std::make_shared<VideoStore>(data_root);
    runs = std::make_shared<RunStore>(data_root);
    replays = std::make_shared<ReplayManager>(videos, runs, data_root / ".last_replay_id");
    mot = std::make_shared<MotStore>(data_root);
    sweeps = std::make_shared<SweepStore>(data_root);
    sectors = std::make_shared<SectorStore>(data_root);
    gaze = std::make_shared<GazeStore>(data_root, GazeStore::Leftovers::remove);
  }
  bundle_streams = std::make_shared<BundleStreams>(store);
  access = std::make_shared<Access>(
      std::make_shared<TokenStore>(data_root.empty() ? data_root : data_root / "tokens.json"));
}

Router make_router(App& app) {
  Router r;
  const auto bind = [&app](Response (*h)(App&, const Request&, const PathParams&)) {
    return [&app, h](const Request& req, const PathParams& p) { return h(app, req, p); };
  };
  // An upload's precheck runs on its header, before the body is read (Router::Route::precheck).
  const auto check = [&app](void (*c)(App&, const Request&, const PathParams&)) {
    return [&app, c](const Request& req, const PathParams& p) { c(app, req, p); };
  };
  // Uploads stream to disk with their own limit; the name is what a 413 calls the body.
  const auto upload = [](std::uint64_t limit, const char* name) { return BodyRule{limit, true, name}; };
  using namespace handlers;
  const Collection<GraphStore> graphs{&App::graphs, "graphs", "graph", "a graph store"};
  const Collection<BundleStore> bundles{&App::bundles, "bundles", "bundle", "a bundle store"};
  const Collection<VideoStore> videos{&App::videos, "videos", "video", "a video store"};
  const Collection<RunStore> runs{&App::runs, "runs", "run", "a run store"};
  const Collection<MotStore> mot{&App::mot, "files", "mot", "a MOT store"};
  const Collection<SweepStore> sweeps{&App::sweeps, "sweeps", "sweep", "run and video stores"};
  // Roles: GET needs a reader's token, every other method a writer's (Router::add); the exceptions say
  // .needs() (the POSTs that only compute an answer need a reader). Lanes: .on(Lane::compute) runs the
  // handler on the compute pool (routes/router.hpp). method  pattern handler          statuses
  r.add("GET", "/api/v1/health", bind(health)).needs(Role::anyone);  // 200
  r.add("GET", "/api/v1/datasets", bind(list_datasets));             // 200
  r.add("POST", "/api/v1/datasets", bind(create_dataset), upload(limits::kMaxUploadBytes, "upload"))
      .checked_first(check(create_dataset_check));                                      // 202 400 409 413
  r.add("GET", "/api/v1/datasets/{dataset}", bind(get_dataset));                        // 200 404
  r.add("DELETE", "/api/v1/datasets/{dataset}", bind(delete_dataset));                  // 204 404
  r.add("GET", "/api/v1/datasets/{dataset}/summary", bind(summary)).on(Lane::compute);  // 200 400 404
  r.add("GET", "/api/v1/datasets/{dataset}/flights", bind(list_flights)).on(Lane::compute);  // 200 400 404
  r.add("GET", "/api/v1/datasets/{dataset}/flights/{flight_id}", bind(get_flight))
      .on(Lane::compute);                                                                   // 200 400 404 413
  r.add("GET", "/api/v1/datasets/{dataset}/positions", bind(positions)).on(Lane::compute);  // 200 400 404 413
  r.add("GET", "/api/v1/datasets/{dataset}/animation", bind(animation))
      .on(Lane::compute);                                   // 200 304 400 404 413
  r.add("GET", "/api/v1/jobs", bind(list_jobs));            // 200
  r.add("GET", "/api/v1/jobs/{job}", bind(get_job));        // 200 404
  r.add("DELETE", "/api/v1/jobs/{job}", bind(cancel_job));  // 200 404
  r.add("GET", "/tiles/{dataset}/density/{z}/{x}/{y}.png", bind(density_tile))
      .on(Lane::compute);                                     // 200 304 400 404
  r.add("GET", "/api/v1/graphs", list_handler(app, graphs));  // 200
  r.add("POST", "/api/v1/graphs", bind(create_graph), upload(limits::kMaxGraphUploadBytes, "graph upload"))
      .checked_first(check(create_graph_check));                           // 201 400 413 415 422
  r.add("GET", "/api/v1/graphs/{graph}", get_handler(app, graphs));        // 200 404
  r.add("DELETE", "/api/v1/graphs/{graph}", delete_handler(app, graphs));  // 204 404
  // /bundles/params before /bundles/{bundle}: the first matching route wins.
  r.add("GET", "/api/v1/bundles/params", bind(bundle_params));          // 200
  r.add("GET", "/api/v1/bundles", list_handler(app, bundles));          // 200
  r.add("POST", "/api/v1/bundles", bind(create_bundle));                // 202 400 404 413 422
  r.add("GET", "/api/v1/bundles/{bundle}", get_handler(app, bundles));  // 200 404
  r.add("DELETE", "/api/v1/bundles/{bundle}", bind(delete_bundle));     // 204 404
  r.add("GET", "/api/v1/bundles/{bundle}/image.png", bind(bundle_image))
      .on(Lane::compute);  // 200 304 400 404
  r.add("GET", "/api/v1/bundles/{bundle}/polylines", bind(bundle_polylines))
      .on(Lane::compute);  // 200 400 404 413
  r.add("GET", "/tiles/{dataset}/bundle/{bundle}/{z}/{x}/{y}.png", bind(bundle_tile))
      .on(Lane::compute);  // 200 304 400 404
  // Depth videos; /videos/synth before /videos/{video}.
  r.add("GET", "/api/v1/videos", list_handler(app, videos));  // 200
  r.add("POST", "/api/v1/videos", bind(create_video), upload(limits::kMaxVideoUploadBytes, "video upload"))
      .checked_first(check(create_video_check));                           // 201 400 409 413 415 422
  r.add("POST", "/api/v1/videos/synth", bind(synth_video));                // 202 400 409 413
  r.add("GET", "/api/v1/videos/{video}", get_handler(app, videos));        // 200 404
  r.add("DELETE", "/api/v1/videos/{video}", delete_handler(app, videos));  // 204 404
  r.add("GET", "/api/v1/videos/{video}/frames/{i}", bind(video_frame));    // 200 400 404
  r.add("GET", "/api/v1/videos/{video}/frames/{i}/depth.png", bind(video_depth_png));          // 200 400 404
  r.add("GET", "/api/v1/videos/{video}/frames/{i}/amplitude.png", bind(video_amplitude_png));  // 200 400 404
  // Tracker runs; /runs/track before /runs/{run}.
  r.add("GET", "/api/v1/tracker/params", bind(tracker_params));  // 200
  r.add("GET", "/api/v1/runs", list_handler(app, runs));         // 200
  r.add("POST", "/api/v1/runs", bind(create_run), upload(limits::kMaxRunBytes, "run upload"))
      .checked_first(check(create_run_check));                       // 201 400 409 413 415
  r.add("POST", "/api/v1/runs/track", bind(track_run));              // 202 400 404 409
  r.add("GET", "/api/v1/runs/{run}", bind(get_run));                 // 200 404
  r.add("DELETE", "/api/v1/runs/{run}", delete_handler(app, runs));  // 204 404
  r.add("GET", "/api/v1/runs/{run}/log", bind(run_log));             // 200 400 404
  r.add("GET", "/api/v1/runs/{run}/frames", bind(run_frames));       // 200 400 404
  // MOTChallenge files and their metrics.
  r.add("GET", "/api/v1/mot", list_handler(app, mot));  // 200
  r.add("POST", "/api/v1/mot", bind(create_mot), upload(limits::kMaxRunBytes, "MOT file upload"))
      .checked_first(check(create_mot_check));                     // 201 400 409 413 422
  r.add("GET", "/api/v1/mot/{mot}", get_handler(app, mot));        // 200 404
  r.add("DELETE", "/api/v1/mot/{mot}", delete_handler(app, mot));  // 204 404
  r.add("POST", "/api/v1/metrics", bind(compute_metrics))
      .needs(Role::reader)
      .on(Lane::compute);  // 200 400 404 413 422
  // Parameter sweeps.
  r.add("GET", "/api/v1/sweeps", list_handler(app, sweeps));               // 200
  r.add("POST", "/api/v1/sweeps", bind(create_sweep));                     // 202 400 404 409 413 422
  r.add("GET", "/api/v1/sweeps/{sweep}", bind(get_sweep));                 // 200 404
  r.add("GET", "/api/v1/importance", bind(importance)).on(Lane::compute);  // 200 400 404 413 422
  r.add("POST", "/api/v1/projections", bind(create_projection))
      .needs(Role::reader)
      .on(Lane::compute);  // 200 400 404 413 422
  r.add("POST", "/api/v1/compare", bind(compare_runs))
      .needs(Role::reader)
      .on(Lane::compute);  // 200 400 404 413 422
  // Live replays.
  r.add("GET", "/api/v1/replays", bind(list_replays));               // 200
  r.add("POST", "/api/v1/replays", bind(create_replay));             // 201 400 404 409
  r.add("GET", "/api/v1/replays/{replay}", bind(get_replay));        // 200 404
  r.add("DELETE", "/api/v1/replays/{replay}", bind(delete_replay));  // 204 404
  // Airspace sectors and congestion counts (a job; its result as JSON or CSV).
  const Collection<SectorStore> sectors{&App::sectors, "sectors", "sectors", "a sector store"};
  r.add("GET", "/api/v1/sectors", list_handler(app, sectors));  // 200
  r.add("POST", "/api/v1/sectors", bind(create_sectors),
        BodyRule{limits::kMaxSectorUploadBytes, false, "sector upload"});      // 201 400 409 413 422
  r.add("GET", "/api/v1/sectors/{sectors}", bind(get_sectors));                // 200 404
  r.add("DELETE", "/api/v1/sectors/{sectors}", delete_handler(app, sectors));  // 204 404
  r.add("POST", "/api/v1/congestion", bind(create_congestion));                // 202 400 404 413 422
  r.add("GET", "/api/v1/congestion/{job}", bind(get_congestion));              // 200 400 404 409
  // The congestion map of simultaneous aircraft (routes/congestion_tiles.cpp).
  r.add("GET", "/api/v1/datasets/{dataset}/congestion/tiles/{z}/{x}/{y}.png",
        bind(congestion_tile))
      .on(Lane::compute);  // 200 304 400 404
  // Flow maps of traffic and of uploaded vector fields (routes/flow.cpp); the cost is checked up front.
  r.add("GET", "/api/v1/datasets/{dataset}/flow", bind(dataset_flow))
      .on(Lane::compute);  // 200 304 400 404 413 422
  r.add("POST", "/api/v1/flow", bind(upload_flow),
        BodyRule{limits::kMaxFlowFieldBytes, false, "vector field"})
      .needs(Role::reader)
      .on(Lane::compute);  // 200 400 413 415 422
  r.add("GET", "/api/v1/datasets/{dataset}/flow/{z}/{x}/{y}.png", bind(dataset_flow_tile))
      .on(Lane::compute);  // 200 304 400 404 413 422
  // WebSocket upgrades: job events, and the viewers of a replay (404 or 409 before the upgrade).
  r.add_websocket("/api/v1/ws", WebSocketKind::events,
                  [](const Request&, const PathParams&) { return Response::status_only(101); });
  r.add_websocket("/api/v1/replays/{replay}/ws", WebSocketKind::replay, bind(replay_viewer_check));
  // Bundles that follow a client's clock (404 or 409 before the upgrade).
  r.add_websocket("/api/v1/datasets/{dataset}/bundles/stream", WebSocketKind::bundle_stream,
                  bind(bundle_stream_check));
  // Access control (auth/access.hpp): signing in and out needs no token; the tokens are the admins'.
  r.add("GET", "/api/v1/session", bind(get_session)).needs(Role::anyone);            // 200
  r.add("POST", "/api/v1/session", bind(create_session)).needs(Role::anyone);        // 200 400 401 429
  r.add("DELETE", "/api/v1/session", bind(delete_session)).needs(Role::anyone);      // 204
  r.add("GET", "/api/v1/tokens", bind(list_tokens)).needs(Role::admin);              // 200
  r.add("POST", "/api/v1/tokens", bind(create_token)).needs(Role::admin);            // 201 400 409
  r.add("DELETE", "/api/v1/tokens/{token}", bind(revoke_token)).needs(Role::admin);  // 204 404
  // The flight dashboard: picking on the density map, exports, data quality.
  r.add("GET", "/api/v1/datasets/{dataset}/pick", bind(pick)).on(Lane::compute);  // 200 400 404
  r.add("GET", "/api/v1/datasets/{dataset}/export", bind(export_flights))
      .on(Lane::compute);  // 200 400 404 413
  r.add("GET", "/api/v1/datasets/{dataset}/density/legend", bind(density_legend))
      .on(Lane::compute);  // 200 400 404
  // Stored gaze datasets (routes/gaze.cpp): upload (a job), list, describe, delete; events and scanpaths
  // under the shared gaze filters; stimulus images.
  r.add("GET", "/api/v1/gaze", bind(list_gaze));  // 200
  r.add("POST", "/api/v1/gaze", bind(create_gaze), upload(limits::kMaxGazeUploadBytes, "gaze upload"))
      .checked_first(check(create_gaze_check));                                           // 202 400 409 413
  r.add("GET", "/api/v1/gaze/{gaze}", bind(get_gaze));                                    // 200 404
  r.add("DELETE", "/api/v1/gaze/{gaze}", bind(delete_gaze));                              // 204 403 404
  r.add("GET", "/api/v1/gaze/{gaze}/events", bind(gaze_events)).on(Lane::compute);        // 200 400 404 413
  r.add("GET", "/api/v1/gaze/{gaze}/scanpaths", bind(gaze_scanpaths)).on(Lane::compute);  // 200 400 404 413
  r.add("PUT", "/api/v1/gaze/{gaze}/stimulus", bind(put_gaze_stimulus),
        BodyRule{limits::kMaxGazeStimulusBytes,
                 false,
                 "stimulus image",
                 {"image/png", "image/jpeg"}});                           // 200 400 403 404 413 415 422
  r.add("GET", "/api/v1/gaze/{gaze}/stimulus", bind(get_gaze_stimulus));  // 200 400 404
  // Gaze views (routes/gaze_views.cpp): stimulus-space density tiles and their legend, AOI measures (a
  // query that changes nothing: reader), saccade bundling (a job whose result is a bundle of /bundles).
  r.add("GET", "/api/v1/gaze/{gaze}/tiles/legend", bind(gaze_tile_legend))
      .on(Lane::compute);  // 200 400 404 413 422
  r.add("GET", "/api/v1/gaze/{gaze}/tiles/{z}/{x}/{y}.png", bind(gaze_tile))
      .on(Lane::compute);  // 200 304 400 404 413 422
  r.add("POST", "/api/v1/gaze/{gaze}/aoi", bind(gaze_aoi))
      .needs(Role::reader)
      .on(Lane::compute);                                                            // 200 400 404 413 422
  r.add("POST", "/api/v1/gaze/{gaze}/bundle", bind(gaze_bundle)).on(Lane::compute);  // 202 400 404 413 422
  r.set_access(access_check(app.access));
  r.set_fallback(bind(static_file));
  return r;
}

}  // namespace trailscope::server
