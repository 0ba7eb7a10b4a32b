// Flow maps (compute/.../flow/render.hpp, flow_image):
//   GET  /api/v1/datasets/{dataset}/flow   the flow map of a dataset's traffic under the window filters
//   POST /api/v1/flow                      the flow map of an uploaded vector field (proto/flow_field.md)
//   GET  /api/v1/datasets/{dataset}/flow/{z}/{x}/{y}.png   XYZ tiles of the dataset's flow map (lines layer)
// The first two take the flow options as query parameters (the CLI's --param names) and `format=png|json`:
// the image, or the streamlines at `level` as JSON. The cost is checked by flow_image before any point is
// read (limits::kMaxFlowLinePoints, kMaxFlowImagePx, kMaxFlowGridCells); all run on the compute lane.
// The tiles take the same window filters and field, streamline and bundling parameters, plus `level`,
// `line_width` and `size`: the map is computed once per dataset, window and those parameters (App::flow_maps,
// its cost checked by flow_map before any point is read) and each tile draws the lines that reach it.
#include "params/query_params.hpp"
#include "params/tile_params.hpp"
#include "routes/handlers.hpp"
#include "routes/png_cache.hpp"
#include "routes/router.hpp"
#include "trailscope/bundling/params.hpp"
#include "trailscope/density/png.hpp"
#include "trailscope/flow/render.hpp"

namespace trailscope::server::handlers {
namespace {

/// The flow option names a request may give (besides the window filters and `format`).
std::vector<std::string> flow_keys(bool with_window) {
  std::vector<std::string> keys = {
      "format",     "level",      "cell_px",     "line_width",    "halo_px",        "background", "cmap",
      "grid",       "sectors",    "smooth",      "max_gap",       "d_sep",          "d_test",     "step",
      "integrator", "min_length", "min_traffic", "min_coherence", "max_line_points"};
  for (const auto& info : bundling::parameter_infos()) keys.push_back("bundle." + info.name);
  return with_window ? params::with_query_keys(std::move(keys)) : keys;
}

struct Options {
  flow::FlowParams params;
  flow::FlowRenderParams render;
  bool json = false;
  std::string canonical;  ///< the options as text, in name order (for the cache key)
};

Options parse_options(const Request& req) {
  Options o;
  const std::string format = params::text(req, "format", "png");
  if (format != "png" && format != "json") throw invalid_argument("format", "format must be png or json");
  o.json = format == "json";
  const auto& window = params::query_keys();
  for (const auto& [k, v] : req.query) {
    if (k == "format" || std::find(window.begin(), window.end(), k) != window.end()) continue;
    flow::set_flow_option(o.params, o.render, k, v);
    o.canonical += "&" + k + "=" + v;
  }
  return o;
}

Response answer(const flow::FlowImage& r, const Options& o) {
  if (o.json) {
    nlohmann::json j = flow::flow_json(r.map, o.render.level);
    j["times"]["render_ms"] = r.render_ms;
    j["width"] = r.image.width, j["height"] = r.image.height;
    return Response::json(200, j);
  }
  Response res;
  res.content_type = "image/png";
  res.body = density::encode_png(r.image);
  return res;
}

/// The option names of a flow tile: what shapes the map (field, streamlines, bundling) and how a tile
/// draws it (level, line_width), besides the window filters and the tile size.
std::vector<std::string> flow_tile_keys() {
  std::vector<std::string> keys = {"size",        "level",         "line_width",     "grid",
                                   "sectors",     "smooth",        "max_gap",        "d_sep",
                                   "d_test",      "step",          "integrator",     "min_length",
                                   "min_traffic", "min_coherence", "max_line_points"};
  for (const auto& info : bundling::parameter_infos()) keys.push_back("bundle." + info.name);
  return params::with_query_keys(std::move(keys));
}

}  // namespace

Response dataset_flow_tile(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, flow_tile_keys());
  const auto ds = app.store->get(p.at("dataset"));
  const Query q = parse_query(req.query);
  const params::TileCoords c = params::tile_coords(req, p);
  flow::FlowParams fp;
  flow::FlowRenderParams rp;
  std::string map_options, tile_options;  // in name order (the query is a sorted map)
  const auto& window = params::query_keys();
  for (const auto& [k, v] : req.query) {
    if (k == "size" || std::find(window.begin(), window.end(), k) != window.end()) continue;
    if (k == "level" || k == "line_width") {
      rp.set(k, v);
      tile_options += "&" + k + "=" + v;
    } else {
      fp.set(k, v);
      map_options += "&" + k + "=" + v;
    }
  }
  // Every input that changes the map, and then the tile's bytes.
  const std::string dataset_key = params::dataset_cache_key(ds->id, ds->created);
  const std::string map_key = dataset_key + "/flow?" + q.canonical() + map_options;
  const std::string key = dataset_key + "/flow/" + std::to_string(c.z) + "/" + std::to_string(c.x) + "/" +
                          std::to_string(c.y) + "?" + q.canonical() + map_options + tile_options +
                          "&size=" + std::to_string(c.size);
  return cached_png(app.tiles, key, req, [&] {
    const FlowMapCache::Map map = app.flow_maps.get(
        map_key, [&] { return flow::flow_map(*ds->trails, q, fp, default_backend(), {}, req.cancel.get()); });
    return density::encode_png(flow::render_flow_tile(*map, geo::TileId{c.z, c.x, c.y}, c.size, rp));
  });
}

Response dataset_flow(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, flow_keys(true));
  const auto ds = app.store->get(p.at("dataset"));
  const Query q = parse_query(req.query);
  const Options o = parse_options(req);
  const auto run = [&] {
    return flow::flow_image(*ds->trails, q, o.params, o.render, default_backend(), {}, req.cancel.get());
  };
  if (o.json) return answer(run(), o);
  // Every input that changes the bytes: the dataset, the window, the options.
  const std::string key =
      params::dataset_cache_key(ds->id, ds->created) + "/flow?" + q.canonical() + o.canonical;
  return cached_png(app.tiles, key, req, [&] { return density::encode_png(run().image); });
}

Response upload_flow(App&, const Request& req, const PathParams&) {
  reject_unknown_params(req, flow_keys(false));
  const Options o = parse_options(req);
  flow::VectorField field = flow::parse_field(req.body);
  return answer(
      flow::flow_image(std::move(field), o.params, o.render, default_backend(), {}, req.cancel.get()), o);
}

}  // namespace trailscope::server::handlers
