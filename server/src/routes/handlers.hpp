#pragma once
// Route handlers, one file per resource. Each parses, calls compute/ or the store, and serialises.
#include "routes/app.hpp"

namespace trailscope::server::handlers {

Response health(App& app, const Request& req, const PathParams& p);

Response list_datasets(App& app, const Request& req, const PathParams& p);
Response create_dataset(App& app, const Request& req, const PathParams& p);
Response get_dataset(App& app, const Request& req, const PathParams& p);
Response delete_dataset(App& app, const Request& req, const PathParams& p);

Response summary(App& app, const Request& req, const PathParams& p);
Response list_flights(App& app, const Request& req, const PathParams& p);
Response get_flight(App& app, const Request& req, const PathParams& p);
/// Every flight at the instant `t`, interpolated (trailscope/trails/positions.hpp), as JSON or GeoJSON.
Response positions(App& app, const Request& req, const PathParams& p);
/// One animation chunk [t, t+duration) as TSAN (proto/animation_chunks.md), cached, with ETag and 304.
Response animation(App& app, const Request& req, const PathParams& p);

Response list_jobs(App& app, const Request& req, const PathParams& p);
Response get_job(App& app, const Request& req, const PathParams& p);
Response cancel_job(App& app, const Request& req, const PathParams& p);

Response density_tile(App& app, const Request& req, const PathParams& p);
/// The thresholded congestion map of simultaneous aircraft (trailscope/congestion/congestion_map.hpp).
Response congestion_tile(App& app, const Request& req, const PathParams& p);

/// Flow maps (trailscope/flow/render.hpp): of a dataset's traffic, and of an uploaded vector field.
Response dataset_flow(App& app, const Request& req, const PathParams& p);
Response upload_flow(App& app, const Request& req, const PathParams& p);
/// XYZ tiles of a dataset's flow map (its lines layer; flow::render_flow_tile), from App::flow_maps.
Response dataset_flow_tile(App& app, const Request& req, const PathParams& p);

Response create_graph(App& app, const Request& req, const PathParams& p);

Response bundle_params(App& app, const Request& req, const PathParams& p);
Response create_bundle(App& app, const Request& req, const PathParams& p);
Response delete_bundle(App& app, const Request& req, const PathParams& p);
Response bundle_image(App& app, const Request& req, const PathParams& p);
Response bundle_polylines(App& app, const Request& req, const PathParams& p);
Response bundle_tile(App& app, const Request& req, const PathParams& p);

Response create_video(App& app, const Request& req, const PathParams& p);
Response synth_video(App& app, const Request& req, const PathParams& p);
Response video_frame(App& app, const Request& req, const PathParams& p);
Response video_depth_png(App& app, const Request& req, const PathParams& p);
Response video_amplitude_png(App& app, const Request& req, const PathParams& p);

Response tracker_params(App& app, const Request& req, const PathParams& p);
Response create_run(App& app, const Request& req, const PathParams& p);
Response track_run(App& app, const Request& req, const PathParams& p);
Response get_run(App& app, const Request& req, const PathParams& p);
Response run_log(App& app, const Request& req, const PathParams& p);
Response run_frames(App& app, const Request& req, const PathParams& p);

Response create_mot(App& app, const Request& req, const PathParams& p);
Response compute_metrics(App& app, const Request& req, const PathParams& p);

Response create_sweep(App& app, const Request& req, const PathParams& p);
Response get_sweep(App& app, const Request& req, const PathParams& p);
Response importance(App& app, const Request& req, const PathParams& p);
Response create_projection(App& app, const Request& req, const PathParams& p);
Response compare_runs(App& app, const Request& req, const PathParams& p);

Response list_replays(App& app, const Request& req, const PathParams& p);
Response create_replay(App& app, const Request& req, const PathParams& p);
Response get_replay(App& app, const Request& req, const PathParams& p);
Response delete_replay(App& app, const Request& req, const PathParams& p);
/// The check of a replay's WebSocket upgrade: 404 "replay" when unknown, 409 when it has its
/// limits::kMaxReplayViewers viewers; else 101.
Response replay_viewer_check(App& app, const Request& req, const PathParams& p);
/// The check of a bundle stream's WebSocket upgrade: 404 "dataset" when unknown, 409 "stream" when
/// limits::kMaxBundleStreams streams are open, 400 for any query parameter.
Response bundle_stream_check(App& app, const Request& req, const PathParams& p);

/// Airspace sectors: an upload (a GeoJSON FeatureCollection, congestion::parse_sectors) stored whole; its
/// GeoJSON back. Congestion counts: a job (jobs/congestion_job.hpp); its result as JSON or CSV.
Response create_sectors(App& app, const Request& req, const PathParams& p);
Response get_sectors(App& app, const Request& req, const PathParams& p);
Response create_congestion(App& app, const Request& req, const PathParams& p);
Response get_congestion(App& app, const Request& req, const PathParams& p);

Response static_file(App& app, const Request& req, const PathParams& p);

/// Browser sessions (auth/access.hpp): who is signed in; sign in with {"login": one-time code} or
/// {"token": "tsk_..."} (sets the trailscope_session cookie); sign out. API tokens, for admins: list,
/// create (the token text is in the answer, once), revoke.
Response get_session(App& app, const Request& req, const PathParams& p);
Response create_session(App& app, const Request& req, const PathParams& p);
Response delete_session(App& app, const Request& req, const PathParams& p);
Response list_tokens(App& app, const Request& req, const PathParams& p);
Response create_token(App& app, const Request& req, const PathParams& p);
Response revoke_token(App& app, const Request& req, const PathParams& p);
/// The flight dashboard's picking, sorted flight list, exports and data-quality flags: the flights drawn
/// nearest a point of the density map (trails/pick.hpp).
Response pick(App& app, const Request& req, const PathParams& p);
/// The window's flights as GeoJSON or CSV (trails/export.hpp), size-checked, then streamed.
Response export_flights(App& app, const Request& req, const PathParams& p);
/// The legend of the density tiles of one zoom: data values and colours of the shading applied
/// (density/legend.hpp).
Response density_legend(App& app, const Request& req, const PathParams& p);
// Prechecks of the upload routes (Router::Route::precheck): each runs on the header, before the body is
// read, the checks its handler runs first (parameters, name, room), and throws what the handler would.
void create_dataset_check(App& app, const Request& req, const PathParams& p);
void create_graph_check(App& app, const Request& req, const PathParams& p);
void create_video_check(App& app, const Request& req, const PathParams& p);
void create_run_check(App& app, const Request& req, const PathParams& p);
void create_mot_check(App& app, const Request& req, const PathParams& p);

/// Stored gaze datasets (store/gaze_store.hpp): an upload ingested by a job (jobs/gaze_ingest_job.hpp) and
/// its precheck (name, room, parameters), list, describe, delete; the events and scanpaths of a selection
/// (gaze/query.hpp, params/gaze_filters.hpp); a stimulus image stored and served.
void create_gaze_check(App& app, const Request& req, const PathParams& p);
Response create_gaze(App& app, const Request& req, const PathParams& p);
Response list_gaze(App& app, const Request& req, const PathParams& p);
Response get_gaze(App& app, const Request& req, const PathParams& p);
Response delete_gaze(App& app, const Request& req, const PathParams& p);
Response gaze_events(App& app, const Request& req, const PathParams& p);
Response gaze_scanpaths(App& app, const Request& req, const PathParams& p);
Response put_gaze_stimulus(App& app, const Request& req, const PathParams& p);
Response get_gaze_stimulus(App& app, const Request& req, const PathParams& p);

/// The views of a stored gaze dataset (routes/gaze_views.cpp, compute gazeview/): density tiles in stimulus
/// pixel space and their legend, AOI measures, saccade bundling (a job; the result is a bundle of the
/// bundle store).
Response gaze_tile(App& app, const Request& req, const PathParams& p);
Response gaze_tile_legend(App& app, const Request& req, const PathParams& p);
Response gaze_aoi(App& app, const Request& req, const PathParams& p);
Response gaze_bundle(App& app, const Request& req, const PathParams& p);

}  // namespace trailscope::server::handlers
