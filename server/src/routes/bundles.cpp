#include <charconv>
#include <cmath>

#include "routes/bundle_body.hpp"
#include "routes/handlers.hpp"
#include "routes/params.hpp"
#include "routes/png_cache.hpp"
#include "store/bundle_export.hpp"
#include "store/bundle_request.hpp"
#include "trailscope/bundling/render.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/density/png.hpp"

namespace trailscope::server::handlers {

namespace {
BundleStore& bundle_store(App& app) {
  if (!app.bundles) throw Error(Error::Kind::internal, "", "this server was started without a bundle store");
  return *app.bundles;
}

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

/// The cache key prefix of a bundle: its id and creation stamp (ids are not reused within a run, and
/// the stamp tells a bundle from a later one of the same id after a restart).
std::string bundle_key(const StoredBundle& b) {
  return "bundle:" + b.id + "@" + b.created;
}

double relaxation_param(const Request& req) {
  auto it = req.query.find("relaxation");
  if (it == req.query.end()) return -1;  // the bundle's own
  const std::string& text = it->second;
  double v = 0;
  auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || p != text.data() + text.size() || text.empty() || !std::isfinite(v))
    throw invalid_argument("relaxation", "relaxation: '" + text + "' is not a number");
  if (v < 0 || v > 1) throw invalid_argument("relaxation", "relaxation must lie in 0..1, got " + text);
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

Response list_bundles(App& app, const Request& req, const PathParams&) {
  reject_unknown_params(req, {});
  return Response::json(200, {{"bundles", bundle_store(app).list()}});
}

Response get_bundle(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {});
  return Response::json(200, bundle_store(app).meta(p.at("bundle")));
}

Response delete_bundle(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {});
  const std::string id = p.at("bundle");
  bundle_store(app).remove(id);
  app.tiles.erase_prefix("bundle:" + id + "@");
  return Response::no_content();
}

Response create_bundle(App& app, const Request& req, const PathParams&) {
  reject_unknown_params(req, {});
  BundleStore& bundles = bundle_store(app);
  const BundleRequest br = parse_bundle_request(req.body);
  // The input is gathered now, so an unknown source, an empty window or too many trails is this request's
  // 404/422/413 rather than a failed job; only the bundling itself runs in the job.
  auto in = std::make_shared<BundleInput>();
  if (!br.dataset.empty()) {
    const auto ds = app.store->get(br.dataset);
    *in = input_from_dataset(*ds, br.query, br.max_gap, br.params);
  } else {
    if (!app.graphs) throw Error(Error::Kind::internal, "", "this server was started without a graph store");
    const auto g = app.graphs->get(br.graph);
    *in = input_from_graph(
        g->graph, br.params,
        {{"graph", g->id}, {"name", g->name}, {"format", bundling::to_string(g->graph.format)}});
  }
  const std::string id = bundles.reserve_id();
  const auto store = app.bundles;
  const JobState job =
      app.jobs.submit("bundle", br.dataset.empty() ? br.graph : br.dataset,
                      [store, in, id, params = br.params, backend = br.backend](const ProgressFn& progress,
                                                                                const CancelToken& cancel) {
                        const auto sb = run_bundle(std::move(*in), id, params, backend, progress, &cancel);
                        // Bundles evicted beyond kMaxStoredBundles keep their cached tiles until the LRU
                        // drops them: their keys can never be asked for again.
                        store->put(sb);
                        return sb->to_json();
                      });
  Response res = Response::json(202, {{"job", job.to_json()}, {"bundle", id}});
  res.headers.emplace_back("Location", "/api/v1/jobs/" + job.id);
  return res;
}

Response bundle_image(App& app, const Request& req, const PathParams& p) {
  std::vector<std::string> allowed = render_keys();
  allowed.insert(allowed.end(), {"width", "height"});
  reject_unknown_params(req, allowed);
  const auto b = bundle_store(app).get(p.at("bundle"));
  std::string key = bundle_key(*b) + "/image?";
  const bundling::RenderParams rp = render_params(req, key);
  // RenderParams::validate keeps width and height within limits::kMaxBundleImagePx (a 400 naming them).
  return cached_png(app.tiles, key, req,
                    [&] { return density::encode_png(bundling::render_bundle(b->bundled, rp)); });
}

Response bundle_tile(App& app, const Request& req, const PathParams& p) {
  std::vector<std::string> allowed = render_keys();
  allowed.push_back("size");
  reject_unknown_params(req, allowed);
  const auto ds = app.store->get(p.at("dataset"));
  const auto b = bundle_store(app).get(p.at("bundle"));
  if (b->dataset != ds->id)
    throw not_found("bundle", "bundle '" + b->id + "' is not a bundle of dataset '" + ds->id + "'");
  const int z = static_cast<int>(params::path_integer(p, "z", limits::kMinZoom, limits::kMaxZoom));
  const std::int64_t n = std::int64_t{1} << z;
  const int x = static_cast<int>(params::path_integer(p, "x", 0, n - 1));
  const int y = static_cast<int>(params::path_integer(p, "y", 0, n - 1));
  const int size = static_cast<int>(
      params::integer(req, "size", limits::kTileSizeSmall, limits::kTileSizeSmall, limits::kTileSizeLarge));
  if (size != limits::kTileSizeSmall && size != limits::kTileSizeLarge)
    throw invalid_argument("size", "size must be 256 or 512");
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
  const auto b = bundle_store(app).get(p.at("bundle"));
  if (format == "json") return Response::json(200, polylines_json(*b, relaxation));
  Response res;
  res.content_type = "application/octet-stream";
  res.body = polylines_binary(*b, relaxation);
  return res;
}

}  // namespace trailscope::server::handlers
