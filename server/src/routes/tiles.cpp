#include <limits>

#include "routes/handlers.hpp"
#include "routes/png_cache.hpp"
#include "store/dataset_reads.hpp"
#include "params/query_params.hpp"
#include "params/tile_params.hpp"
#include "trailscope/core/backend.hpp"
#include "limits.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/core/text.hpp"

namespace trailscope::server::handlers {

namespace {
// The shading parameters of a density tile (value, how, cmap, kernel, min_level) into `t`.
void shading_params(const Request& req, density::TileRequest& t) {
  t.value = density::parse_density_value(params::text(req, "value", "count"), "value");
  t.how = density::parse_how(params::text(req, "how", "eq_hist"), "how");
  t.cmap = params::text(req, "cmap", "fire");
  t.kernel_radius = static_cast<int>(params::integer(req, "kernel", 0, 0, limits::kMaxKernelRadiusPx));
  if (req.query.count("min_level")) t.min_level = params::number(req, "min_level", 0);
  // Flights are already split at long gaps when ingested (SO6 keeps its own flight ids and long
  // simplified legs), so every segment of a stored flight is drawn.
  t.max_gap_seconds = std::numeric_limits<double>::infinity();
}
}  // namespace

Response density_tile(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req,
                        params::with_query_keys({"value", "how", "cmap", "size", "kernel", "min_level"}));
  const auto ds = app.store->describe(p.at("dataset"));
  const Query q = parse_query(req.query);
  const params::TileCoords c = params::tile_coords(req, p);
  density::TileRequest t;
  t.tile = geo::TileId{c.z, c.x, c.y};
  t.size = c.size;
  shading_params(req, t);

  // Every input that changes the bytes, and nothing else (the backend gives identical bytes).
  const std::string dataset_key = params::dataset_cache_key(ds->id, ds->created);
  const std::string key = dataset_key + "/" + std::to_string(c.z) + "/" + p.at("x") + "/" + p.at("y") + "?" +
                          q.canonical() + "&value=" + density::to_string(t.value) +
                          "&how=" + density::to_string(t.how) + "&cmap=" + t.cmap +
                          "&size=" + std::to_string(t.size) + "&kernel=" + std::to_string(t.kernel_radius) +
                          "&min_level=" + format_double(density::effective_min_level(t));
  density::validate(t);  // before the ETag check: a malformed request never gets a 304
  return cached_png(app.tiles, key, req,
                    [&] { return reads_of(*app.store).density_tile(*ds, app.density, dataset_key, q, t); });
}

Response density_legend(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(
      req, params::with_query_keys({"z", "value", "how", "cmap", "size", "kernel", "min_level", "stops"}));
  const auto ds = app.store->describe(p.at("dataset"));
  const Query q = parse_query(req.query);
  if (!req.query.count("z")) throw invalid_argument("z", "z: the zoom of the tiles is required (?z=)");
  const params::TileCoords c = params::tile_coords(req, {{"z", req.query.at("z")}, {"x", "0"}, {"y", "0"}});
  density::TileRequest t;
  t.tile = geo::TileId{c.z, 0, 0};
  t.size = c.size;
  shading_params(req, t);
  const auto stops = static_cast<int>(params::integer(req, "stops", 11, 2, limits::kMaxLegendStops));
  const std::string dataset_key = params::dataset_cache_key(ds->id, ds->created);
  nlohmann::json j =
      reads_of(*app.store).density_legend(*ds, app.density, dataset_key, q, t, stops).to_json();
  j["dataset"] = ds->id;
  j["query"] = q.canonical();
  j["z"] = c.z;
  j["size"] = c.size;
  j["value"] = density::to_string(t.value);
  j["unit"] = t.value == density::DensityValue::count      ? "segments per pixel"
              : t.value == density::DensityValue::altitude ? "m"
                                                           : "m/s";
  j["how"] = density::to_string(t.how);
  j["cmap"] = t.cmap;
  j["kernel"] = t.kernel_radius;
  j["min_level"] = density::effective_min_level(t);
  return Response::json(200, j);
}

}  // namespace trailscope::server::handlers
