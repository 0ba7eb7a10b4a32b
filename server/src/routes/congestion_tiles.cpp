// GET /api/v1/datasets/{dataset}/congestion/tiles/{z}/{x}/{y}.png: the thresholded congestion map of
// simultaneous aircraft (compute/.../congestion/congestion_map.hpp), at an instant (?t=) or averaged over
// a window (?t0=&t1=), cached and ETagged like the density tiles (routes/tiles.cpp).
#include <optional>

#include "params/query_params.hpp"
#include "params/tile_params.hpp"
#include "routes/handlers.hpp"
#include "routes/png_cache.hpp"
#include "trailscope/congestion/congestion_map.hpp"
#include "trailscope/core/text.hpp"
#include "trailscope/density/span.hpp"

namespace trailscope::server::handlers {

Response congestion_tile(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, params::with_query_keys({"t", "threshold", "vmax", "how", "cmap", "size"}));
  const auto ds = app.store->get(p.at("dataset"));
  const Query q = parse_query(req.query);
  const params::TileCoords c = params::tile_coords(req, p);
  congestion::CongestionTileRequest t;
  t.tile = geo::TileId{c.z, c.x, c.y};
  t.size = c.size;
  if (const auto it = req.query.find("t"); it != req.query.end()) t.t = parse_time(it->second, "t");
  t.threshold = params::number(req, "threshold", 1.0);
  if (req.query.count("vmax")) t.vmax = params::number(req, "vmax", 0.0);
  const std::string how = params::text(req, "how", "linear");
  t.how = density::parse_how(how, "how");
  t.cmap = params::text(req, "cmap", "fire");
  congestion::validate(t, q);  // before the ETag check: a malformed request never gets a 304

  // Every input that changes the bytes, and nothing else.
  const std::string dataset_key = params::dataset_cache_key(ds->id, ds->created);
  std::string key = dataset_key + "/congestion/" + std::to_string(c.z) + "/" + std::to_string(c.x) + "/" +
                    std::to_string(c.y) + "?" + q.canonical() + "&threshold=" + format_double(t.threshold) +
                    "&how=" + how + "&cmap=" + t.cmap + "&size=" + std::to_string(t.size);
  if (t.t) key += "&t=" + format_double(*t.t);
  if (t.vmax) key += "&vmax=" + format_double(*t.vmax);
  return cached_png(app.tiles, key, req,
                    [&] { return std::move(congestion::render_congestion_tile(*ds->trails, q, t).png); });
}

}  // namespace trailscope::server::handlers
