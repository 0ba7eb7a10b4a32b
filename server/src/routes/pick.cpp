// GET /api/v1/datasets/{dataset}/pick: the flights drawn nearest a point of the density map
// (compute/.../trails/pick.hpp), for hovering and clicking the map.
#include <cmath>

#include "limits.hpp"
#include "params/query_params.hpp"
#include "routes/handlers.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/core/text.hpp"
#include "trailscope/geo/web_mercator.hpp"
#include "trailscope/trails/pick.hpp"

namespace trailscope::server::handlers {

Response pick(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(
      req, params::with_query_keys({"lon", "lat", "x", "y", "zoom", "tile_size", "tolerance", "limit"}));
  const auto ds = app.store->get(p.at("dataset"));
  const Query q = parse_query(req.query);
  PickRequest r;
  if (!req.query.count("zoom")) throw invalid_argument("zoom", "zoom: the map's zoom is required (?zoom=)");
  r.zoom = params::number(req, "zoom", 0);
  r.tile_size = static_cast<int>(params::integer(req, "tile_size", limits::kTileSizeSmall, 0, 1 << 20));
  r.tolerance_px = params::number(req, "tolerance", 5);
  if (!(r.tolerance_px > 0 && r.tolerance_px <= limits::kMaxPickTolerancePx))
    throw invalid_argument(
        "tolerance", "tolerance must lie in (0, " + format_double(limits::kMaxPickTolerancePx) + "] pixels");
  r.limit = static_cast<std::size_t>(params::integer(req, "limit", 10, 1, limits::kMaxPickResults));
  const bool geo_point = req.query.count("lon") || req.query.count("lat");
  const bool px_point = req.query.count("x") || req.query.count("y");
  if (geo_point && px_point)
    throw invalid_argument("x", "give the point either as lon and lat or as x and y, not both");
  if (geo_point) {
    if (!req.query.count("lon") || !req.query.count("lat"))
      throw invalid_argument(req.query.count("lon") ? "lat" : "lon", "lon and lat go together");
    const double lon = params::number(req, "lon", 0), lat = params::number(req, "lat", 0);
    if (!(lat >= -90 && lat <= 90)) throw invalid_argument("lat", "lat must lie in [-90, 90]");
    r.x = geo::lon_to_unit_x(lon), r.y = geo::lat_to_unit_y(lat);
  } else if (px_point) {
    if (!req.query.count("x") || !req.query.count("y"))
      throw invalid_argument(req.query.count("x") ? "y" : "x", "x and y go together");
    // World pixels at the zoom: the tile column times tile_size plus the pixel in the tile.
    const double x = params::number(req, "x", 0), y = params::number(req, "y", 0);
    // Checked here first, so that the world's size below is that of a valid zoom and tile size.
    validate_pick(r);
    const double world = r.tile_size * std::exp2(r.zoom);
    if (!(y >= 0 && y <= world))
      throw invalid_argument("y",
                             "y must lie in [0, " + format_double(world) + "] (world pixels at this zoom)");
    r.x = x / world, r.y = y / world;
  } else {
    throw invalid_argument("lon", "the point is required: lon and lat, or x and y in world pixels");
  }
  const auto hits = pick_flights(*ds->trails, q, r);
  nlohmann::json list = nlohmann::json::array();
  for (const auto& h : hits)
    list.push_back({{"id", h.id},
                    {"icao24", h.icao24},
                    {"callsign", h.callsign},
                    {"distance_px", h.distance_px},
                    {"t", h.t},
                    {"lon", h.lon},
                    {"lat", h.lat},
                    {"alt_m", number_or_null(h.alt_m)}});
  return Response::json(200, {{"dataset", ds->id},
                              {"query", q.canonical()},
                              {"zoom", r.zoom},
                              {"tile_size", r.tile_size},
                              {"tolerance_px", r.tolerance_px},
                              {"flights", std::move(list)}});
}

}  // namespace trailscope::server::handlers
