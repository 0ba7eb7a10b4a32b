#include <limits>

#include "routes/handlers.hpp"
#include "routes/png_cache.hpp"
#include "params/query_params.hpp"
#include "params/tile_params.hpp"
#include "trailscope/core/backend.hpp"
#include "trailscope/core/limits.hpp"

namespace trailscope::server::handlers {

Response density_tile(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, params::with_query_keys({"value", "how", "cmap", "size", "kernel"}));
  const auto ds = app.store->get(p.at("dataset"));
  const Query q = parse_query(req.query);
  const params::TileCoords c = params::tile_coords(req, p);
  density::TileRequest t;
  t.tile = geo::TileId{c.z, c.x, c.y};
  t.size = c.size;
  const std::string value = params::text(req, "value", "count"), how = params::text(req, "how", "eq_hist");
  t.value = density::parse_density_value(value, "value");
  t.how = density::parse_how(how, "how");
  t.cmap = params::text(req, "cmap", "fire");
  t.kernel_radius = static_cast<int>(params::integer(req, "kernel", 0, 0, limits::kMaxKernelRadiusPx));
  // Flights are already split at long gaps when ingested (SO6 keeps its own flight ids and long
  // simplified legs), so every segment of a stored flight is drawn.
  t.max_gap_seconds = std::numeric_limits<double>::infinity();

  // Every input that changes the bytes, and nothing else (the backend gives identical bytes).
  const std::string dataset_key = params::dataset_cache_key(ds->id, ds->created);
  const std::string key = dataset_key + "/" + std::to_string(c.z) + "/" + p.at("x") + "/" + p.at("y") + "?" +
                          q.canonical() + "&value=" + value + "&how=" + how + "&cmap=" + t.cmap +
                          "&size=" + std::to_string(t.size) + "&kernel=" + std::to_string(t.kernel_radius);
  density::validate(t);  // before the ETag check: a malformed request never gets a 304
  return cached_png(app.tiles, key, req,
                    [&] { return std::move(app.density.render_tile(*ds->trails, dataset_key, q, t).png); });
}

Response density_scale(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, params::with_query_keys({"z", "value", "how", "size", "kernel"}));
  const auto ds = app.store->get(p.at("dataset"));
  const Query q = parse_query(req.query);
  density::TileRequest t;
  const int z = static_cast<int>(params::integer(req, "z", 0, limits::kMinZoom, limits::kMaxZoom));
  t.tile = geo::TileId{z, 0, 0};
  t.size = static_cast<int>(
      params::integer(req, "size", limits::kTileSizeSmall, limits::kTileSizeSmall, limits::kTileSizeLarge));
  if (t.size != limits::kTileSizeSmall && t.size != limits::kTileSizeLarge)
    throw invalid_argument("size", "size must be 256 or 512");
  const std::string value = params::text(req, "value", "count"), how = params::text(req, "how", "eq_hist");
  t.value = density::parse_density_value(value, "value");
  t.how = density::parse_how(how, "how");
  t.kernel_radius = static_cast<int>(params::integer(req, "kernel", 0, 0, limits::kMaxKernelRadiusPx));
  // The same gap rule as density_tile: the legend describes exactly the span those tiles are shaded with.
  t.max_gap_seconds = std::numeric_limits<double>::infinity();
  bool cached = false;
  const auto span =
      app.density.span_for(*ds->trails, params::dataset_cache_key(ds->id, ds->created), q, t, &cached);
  nlohmann::json j = {{"dataset", ds->id},
                      {"query", q.canonical()},
                      {"z", z},
                      {"value", value},
                      {"how", how},
                      {"unit", value == "count"      ? "segments"
                               : value == "altitude" ? "m"
                                                     : "m/s"},
                      {"empty", span->empty},
                      {"lo", span->lo},
                      {"hi", span->hi},
                      {"samples", span->samples},
                      {"cdf_values", span->cdf_values},
                      {"cdf", span->cdf},
                      {"cached", cached}};
  return Response::json(200, j);
}

}  // namespace trailscope::server::handlers
