// GET /api/v1/datasets/{dataset}/positions: every flight at one instant (compute/.../trails/positions.hpp).
#include "limits.hpp"
#include "params/query_params.hpp"
#include "routes/handlers.hpp"
#include "store/dataset_reads.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/trails/positions.hpp"

namespace trailscope::server::handlers {

Response positions(App& app, const Request& req, const PathParams& p) {
  // t0 and t1 are allowed through here so that positions_at() refuses them by name, rather than the
  // generic "unknown query parameter".
  reject_unknown_params(req, params::with_query_keys({"t", "format", "max_positions"}));
  const auto ds = app.store->describe(p.at("dataset"));
  const auto t_param = req.query.find("t");
  if (t_param == req.query.end())
    throw invalid_argument("t", "t: the instant is required (?t=Unix seconds or ISO 8601)");
  const double t = parse_time(t_param->second, "t");
  const Query q = parse_query(req.query);
  const std::string format = params::text(req, "format", "json");
  if (format != "json" && format != "geojson")
    throw invalid_argument("format", "format must be 'json' or 'geojson', got '" + format + "'");
  const auto max_positions = params::integer(req, "max_positions", limits::kMaxPositionsPerResponse, 1,
                                             limits::kMaxPositionsPerResponse);
  const Positions at = reads_of(*app.store).positions_at(*ds, t, q, static_cast<std::size_t>(max_positions));
  nlohmann::json j = format == "geojson" ? at.to_geojson() : at.to_json();
  j["dataset"] = ds->id;
  Response res = Response::json(200, j);
  if (format == "geojson") res.content_type = "application/geo+json";
  return res;
}

}  // namespace trailscope::server::handlers
