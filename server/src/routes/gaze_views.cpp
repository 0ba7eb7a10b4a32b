// The views of a stored gaze dataset (compute/include/trailscope/gazeview/): density tiles in stimulus
// pixel space and their legend, AOI measures, and saccade bundling (a job whose result is a bundle of the
// bundle store, read at /api/v1/bundles/{bundle}). Every view reads its selection through the one gaze
// filter parser (params/gaze_filters.hpp): from the query string on GET, from the body's fields on POST.
#include <cmath>

#include "jobs/bundle_job.hpp"
#include "limits.hpp"
#include "params/gaze_filters.hpp"
#include "params/json_fields.hpp"
#include "params/query_params.hpp"
#include "params/tile_params.hpp"
#include "routes/handlers.hpp"
#include "routes/png_cache.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/text.hpp"
#include "trailscope/gazeview/aoi.hpp"
#include "trailscope/gazeview/saccade_bundle.hpp"
#include "trailscope/gazeview/tiles.hpp"

namespace trailscope::server::handlers {
namespace {

GazeStore& store_of(App& app) {
  return need(app.gaze, "a gaze store");
}

/// The tile parameters besides the gaze filters.
const std::vector<std::string> kTileKeys{"what", "how", "cmap", "kernel", "min_level"};

/// The shading of a gaze tile (what, how, cmap, kernel, min_level; named as the flight density tiles').
gazeview::StimulusTileRequest tile_request(const Request& req, gazeview::TileWhat& what) {
  gazeview::StimulusTileRequest t;
  what = gazeview::parse_tile_what(params::text(req, "what", "samples"), "what");
  t.how = density::parse_how(params::text(req, "how", "eq_hist"), "how");
  t.cmap = params::text(req, "cmap", "fire");
  t.kernel_radius = double(params::integer(req, "kernel", 0, 0, limits::kMaxKernelRadiusPx));
  if (req.query.count("min_level")) t.min_level = params::number(req, "min_level", 0);
  return t;
}

/// The selected recordings' samples, checked against kMaxGazeViewSamples before anything is drawn (a
/// tile's cost is linear in them, its shared span N log N).
std::vector<std::size_t> bounded_recordings(const gaze::GazeDataset& ds, const gaze::GazeFilter& f) {
  const std::vector<std::size_t> sel = gazeview::pixel_recordings(ds, f);
  std::uint64_t samples = 0;
  for (std::size_t i : sel) samples += ds.recordings[i].size();
  if (samples > limits::kMaxGazeViewSamples)
    throw Error(Error::Kind::payload_too_large, "recording",
                "the filters select " + std::to_string(samples) + " samples; one gaze view reads at most " +
                    std::to_string(limits::kMaxGazeViewSamples) +
                    " (kMaxGazeViewSamples): narrow it with participant, stimulus or recording");
  return sel;
}

}  // namespace

Response gaze_tile(App& app, const Request& req, const PathParams& p) {
  std::vector<std::string> keys = kTileKeys;
  keys.push_back("size");  // accepted as on the flight tiles, and 400 unless 256
  reject_unknown_params(req, params::with_gaze_filter_keys(keys));
  const params::GazeFilters f = params::parse_gaze_filters(req);
  const params::TileCoords c = params::tile_coords(req, p);
  if (c.size != limits::kTileSizeSmall)
    throw invalid_argument("size", "size: gaze tiles are " + std::to_string(limits::kTileSizeSmall) + " px");
  gazeview::TileWhat what;
  gazeview::StimulusTileRequest t = tile_request(req, what);
  t.tile = {c.z, c.x, c.y};
  gazeview::validate(t);  // before the ETag check: a malformed request never gets a 304
  GazeStore& store = store_of(app);
  const std::string id = p.at("gaze");
  const nlohmann::json meta = store.meta(id);
  // Every input that changes the bytes: the dataset (its creation time, so a replaced dataset of the same
  // name misses), the tile and the whole query as JSON (unambiguous whatever the values hold; spelling
  // variants of one value only miss).
  const std::string key = "gaze:" + id + "@" + meta.value("created", "") + "/" + geo::to_string(t.tile) +
                          "?" + nlohmann::json(req.query).dump();
  return cached_png(app.tiles, key, req, [&] {
    const auto ds = store.get(id);
    const std::vector<std::size_t> sel = bounded_recordings(*ds, f.select);
    const gazeview::Stimulus st = gazeview::stimulus_of(*ds, sel);
    const gazeview::GazePoints points =
        gazeview::gaze_points(*ds, f.select, f.events, what, limits::kMaxGazeEvents);
    return std::move(gazeview::render_stimulus_tile(points, st, t).png);
  });
}

Response gaze_tile_legend(App& app, const Request& req, const PathParams& p) {
  std::vector<std::string> keys = kTileKeys;
  keys.insert(keys.end(), {"z", "stops"});
  reject_unknown_params(req, params::with_gaze_filter_keys(keys));
  const params::GazeFilters f = params::parse_gaze_filters(req);
  if (!req.query.count("z")) throw invalid_argument("z", "z: the zoom of the tiles is required (?z=)");
  const params::TileCoords c = params::tile_coords(req, {{"z", req.query.at("z")}, {"x", "0"}, {"y", "0"}});
  gazeview::TileWhat what;
  gazeview::StimulusTileRequest t = tile_request(req, what);
  t.tile = {c.z, 0, 0};
  gazeview::validate(t);
  const auto stops = static_cast<int>(params::integer(req, "stops", 11, 2, limits::kMaxLegendStops));
  const auto ds = store_of(app).get(p.at("gaze"));
  const std::vector<std::size_t> sel = bounded_recordings(*ds, f.select);
  const gazeview::Stimulus st = gazeview::stimulus_of(*ds, sel);
  const gazeview::GazePoints points =
      gazeview::gaze_points(*ds, f.select, f.events, what, limits::kMaxGazeEvents);
  nlohmann::json j = gazeview::stimulus_legend(points, st, t, stops).to_json();
  j["gaze"] = p.at("gaze");
  j["z"] = c.z;
  j["what"] = gazeview::to_string(what);
  j["unit"] = what == gazeview::TileWhat::samples ? "samples per pixel" : "fixation ms per pixel";
  j["how"] = density::to_string(t.how);
  j["cmap"] = t.cmap;
  j["kernel"] = t.kernel_radius;
  j["min_level"] = t.min_level.value_or(density::kDefaultCountMinLevel);
  j["stimulus"] = {{"width_px", st.width_px}, {"height_px", st.height_px}};
  return Response::json(200, j);
}

Response gaze_aoi(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {});
  std::vector<std::string> allowed = params::gaze_filter_keys();
  allowed.push_back("aois");
  const nlohmann::json body = parse_body_object(req.body, allowed);
  if (!body.contains("aois")) throw invalid_argument("aois", "aois: give the areas of interest");
  const std::vector<gazeview::Aoi> aois = gazeview::aois_from_json(body["aois"]);
  const params::GazeFilters f = params::parse_gaze_filters(body);
  const auto ds = store_of(app).get(p.at("gaze"));
  bounded_recordings(*ds, f.select);
  const gazeview::ViewEvents ev = gazeview::view_events(*ds, f.select, f.events, limits::kMaxGazeEvents);
  nlohmann::json j = gazeview::to_json(gazeview::aoi_statistics(aois, ev.fixations), ev.recordings.size());
  j["method"] = gaze::to_string(f.events.method);
  return Response::json(200, j);
}

Response gaze_bundle(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {});
  BundleStore& bundles = need(app.bundles, "a bundle store");
  std::vector<std::string> allowed = params::gaze_filter_keys();
  allowed.insert(allowed.end(), {"params", "backend"});
  const nlohmann::json body = parse_body_object(req.body, allowed);
  const params::GazeFilters f = params::parse_gaze_filters(body);
  bundling::BundleParams bp;
  if (body.contains("params")) {
    const nlohmann::json& ps = body["params"];
    if (!ps.is_object()) throw invalid_argument("params", "params must be an object of bundling parameters");
    for (const auto& [k, v] : ps.items()) bp.set(k, scalar_text(v, k));
  }
  bp.validate();
  const Backend backend = body.contains("backend")
                              ? parse_backend(scalar_text(body["backend"], "backend"), "backend")
                              : default_backend();
  const std::string id = p.at("gaze");
  const auto ds = store_of(app).get(id);
  // The saccades are gathered now, so a bad filter, no saccade or too many is this request's 4xx; only
  // the bundling runs in the job.
  bounded_recordings(*ds, f.select);
  const gazeview::ViewEvents ev = gazeview::view_events(*ds, f.select, f.events, limits::kMaxGazeEvents);
  const gazeview::Stimulus st = gazeview::stimulus_of(*ds, ev.recordings);
  gazeview::SaccadeLines lines = gazeview::saccade_lines(ev.saccades, st, bp);
  if (lines.px.size() > limits::kMaxBundleEdges)
    throw Error(Error::Kind::payload_too_large, "input",
                std::to_string(lines.px.size()) + " saccades; one bundle takes at most " +
                    std::to_string(limits::kMaxBundleEdges) + " (kMaxBundleEdges)");
  nlohmann::json filters = nlohmann::json::object();
  for (const std::string& k : params::gaze_filter_keys())
    if (body.contains(k)) filters[k] = body[k];
  BundleInput in;
  in.input_points = lines.px.points();
  in.source = {{"gaze", id},
               {"filters", filters},
               {"method", gaze::to_string(f.events.method)},
               {"saccades", lines.px.size()},
               {"recordings", ev.recordings.size()},
               {"stimulus", {{"width_px", st.width_px}, {"height_px", st.height_px}}}};
  in.px = std::move(lines.px);
  in.frame = lines.frame;
  in.units = BundleUnits::plane;
  app.jobs.check_quota(req.principal.owner);  // before an id is spent on a refused job
  const std::string bid = bundles.reserve_id();
  const JobState job = submit_bundle(app.jobs, app.bundles, std::move(in), bid, bp, backend, id, app.disk,
                                     req.principal.owner);
  return Response::json_at(202, {{"job", job.to_json()}, {"bundle", bid}}, "/api/v1/jobs/" + job.id);
}

}  // namespace trailscope::server::handlers
