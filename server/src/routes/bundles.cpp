#include <charconv>
#include <cmath>

#include "jobs/bundle_job.hpp"
#include "params/bundle_body.hpp"
#include "routes/handlers.hpp"
#include "routes/ownership.hpp"
#include "params/query_params.hpp"
#include "params/tile_params.hpp"
#include "routes/png_cache.hpp"
#include "formats/bundle_export.hpp"
#include "trailscope/bundling/render.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/density/png.hpp"
#include "limits.hpp"

namespace trailscope::server::handlers {

namespace {

/// RenderParams fields a bundle image or tile takes as query parameters (RenderParams::set names).
const std::vector<std::string>& render_keys() {
  static const std::vector<std::string> keys = {"style",
                                                "color",
                                                "alpha_mode",
                                                "alpha",
                                                "alpha_by_density",
                                                "shading_radius",
                                                "local_max_radius",
                                                "line_width",
                                                "cmap",
                                                "background",
                                                "relaxation"};
  return keys;
}

/// The render parameters of the query (every one set through RenderParams::set, which names a bad one)
/// and the part of the cache key they make: the query's own text, sorted by name (Request::query is).
bundling::RenderParams render_params(const Request& req, std::string& key, bundling::RenderParams rp = {}) {
  for (const auto& [k, v] : req.query) {
    if (k == "size") continue;  // a tile's edge, not a RenderParams field
    rp.set(k, v);
    key += "&" + k + "=" + v;
  }
  rp.validate();
  return rp;
}

std::string bundle_key(const StoredBundle& b) {
  return params::bundle_cache_key(b.id, b.created);
}

double relaxation_param(const Request& req) {
  auto it = req.query.find("relaxation");
  if (it == req.query.end()) return -1;  // the bundle's own
  const double v = params::number(req, "relaxation", 0);
  if (v < 0 || v > 1) throw invalid_argument("relaxation", "relaxation must lie in 0..1, got " + it->second);
  return v;
}
}  // namespace

Response bundle_params(App&, const Request& req, const PathParams&) {
  reject_unknown_params(req, {});
  nlohmann::json list = nlohmann::json::array();
  for (const auto& i : bundling::parameter_infos())
    list.push_back({{"name", i.name},
                    {"type", i.type},
                    {"default", i.default_value},
                    {"range", i.range},
                    {"help", i.help}});
  return Response::json(200, {{"params", std::move(list)}, {"render", render_keys()}});
}

Response delete_bundle(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {});
  const std::string id = p.at("bundle");
  BundleStore& bundles = need(app.bundles, "a bundle store");
  require_owner(req, "bundle", BundleStore::kNoun, id, bundles.meta(id).value("owner", ""));
  bundles.remove(id);
  app.tiles.erase_prefix(params::bundle_cache_prefix(id));
  return Response::no_content();
}

Response create_bundle(App& app, const Request& req, const PathParams&) {
  reject_unknown_params(req, {});
  BundleStore& bundles = need(app.bundles, "a bundle store");
  const BundleRequest br = parse_bundle_request(req.body);
  // The input is gathered now, so an unknown source, an empty window or too many trails is this request's
  // 404/422/413 rather than a failed job; only the bundling itself runs in the job.
  BundleInput in;
  if (!br.dataset.empty()) {
    const auto ds = app.store->get(br.dataset);
    in = input_from_dataset(*ds, br.query, br.max_gap, br.params);
  } else {
    need(app.graphs, "a graph store");
    const auto g = app.graphs->get(br.graph);
    in = input_from_graph(
        g->graph, br.params,
        {{"graph", g->id}, {"name", g->name}, {"format", bundling::to_string(g->graph.format)}});
  }
  app.jobs.check_quota(req.principal.owner);  // before an id is spent on a refused job
  const std::string id = bundles.reserve_id();
  const JobState job =
      submit_bundle(app.jobs, app.bundles, std::move(in), id, br.params, br.backend,
                    br.dataset.empty() ? br.graph : br.dataset, app.disk, req.principal.owner);
  return Response::json_at(202, {{"job", job.to_json()}, {"bundle", id}}, "/api/v1/jobs/" + job.id);
}

Response bundle_image(App& app, const Request& req, const PathParams& p) {
  std::vector<std::string> allowed = render_keys();
  allowed.insert(allowed.end(), {"width", "height"});
  reject_unknown_params(req, allowed);
  const auto b = need(app.bundles, "a bundle store").get(p.at("bundle"));
  std::string key = bundle_key(*b) + "/image?";
  const bundling::RenderParams rp = render_params(req, key);
  // RenderParams::validate keeps width and height within limits::kMaxBundleImagePx (a 400 naming them);
  // the image's area is bounded too, before anything is drawn: rendering needs ~40 bytes per pixel.
  const bundling::Viewport view = bundling::Viewport::whole(b->bundled, rp);
  const std::uint64_t pixels =
      static_cast<std::uint64_t>(view.width) * static_cast<std::uint64_t>(view.height);
  if (pixels > limits::kMaxImagePixels)
    throw Error(Error::Kind::payload_too_large, req.query.count("height") ? "height" : "width",
                "an image of " + std::to_string(view.width) + " × " + std::to_string(view.height) + " = " +
                    std::to_string(pixels) + " pixels is larger than one request may render: " +
                    std::to_string(limits::kMaxImagePixels) +
                    " pixels (kMaxImagePixels); ask for a smaller width or height, or use the map tiles");
  return cached_png(app.tiles, key, req,
                    [&] { return density::encode_png(bundling::render_bundle(b->bundled, rp)); });
}

Response bundle_tile(App& app, const Request& req, const PathParams& p) {
  std::vector<std::string> allowed = render_keys();
  allowed.push_back("size");
  reject_unknown_params(req, allowed);
  const auto ds = app.store->get(p.at("dataset"));
  const auto b = need(app.bundles, "a bundle store").get(p.at("bundle"));
  if (b->dataset != ds->id)
    throw not_found("bundle", "bundle '" + b->id + "' is not a bundle of dataset '" + ds->id + "'");
  const params::TileCoords c = params::tile_coords(req, p);
  const int z = c.z, x = c.x, y = c.y, size = c.size;
  std::string key = bundle_key(*b) + "/tile/" + std::to_string(z) + "/" + std::to_string(x) + "/" +
                    std::to_string(y) + "?size=" + std::to_string(size);
  // Tiles lie over the basemap: transparent where no line is, unless the query asks otherwise.
  bundling::RenderParams base;
  base.background = "transparent";
  const bundling::RenderParams rp = render_params(req, key, base);
  return cached_png(app.tiles, key, req, [&] {
    return density::encode_png(bundling::render_bundle_tile(b->bundled, rp, z, x, y, size));
  });
}

Response bundle_polylines(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {"format", "relaxation"});
  const auto it = req.query.find("format");
  const std::string format = it == req.query.end() ? "json" : it->second;
  if (format != "json" && format != "binary")
    throw invalid_argument("format", "format must be json or binary, got '" + format + "'");
  const double relaxation = relaxation_param(req);
  const auto b = need(app.bundles, "a bundle store").get(p.at("bundle"));
  if (format == "json") return Response::json(200, polylines_json(*b, relaxation));
  Response res;
  res.content_type = "application/octet-stream";
  res.body = polylines_binary(*b, relaxation);
  return res;
}

}  // namespace trailscope::server::handlers
