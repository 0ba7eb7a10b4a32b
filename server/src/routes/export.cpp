// GET /api/v1/datasets/{dataset}/export: the window's flights as GeoJSON or CSV, planned and size-checked
// first (trails/export.hpp), then streamed a piece at a time (formats/flight_export.hpp, chunked).
#include "formats/flight_export.hpp"
#include "limits.hpp"
#include "params/query_params.hpp"
#include "routes/handlers.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::server::handlers {

Response export_flights(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, params::with_query_keys({"format", "max_points"}));
  const std::shared_ptr<const Dataset> ds = app.store->get(p.at("dataset"));
  const Query q = parse_query(req.query);
  const FlightExportFormat format = parse_flight_export_format(params::text(req, "format", "geojson"));
  const auto max_points = static_cast<std::uint64_t>(
      params::integer(req, "max_points", static_cast<std::int64_t>(limits::kMaxExportPoints), 1,
                      static_cast<std::int64_t>(limits::kMaxExportPoints)));
  ExportPlan plan = plan_export(*ds->trails, q, max_points);
  const bool geojson = format == FlightExportFormat::geojson;
  Response res;
  res.content_type = geojson ? "application/geo+json" : "text/csv; charset=utf-8";
  res.headers.emplace_back("Content-Disposition", "attachment; filename=\"" + ds->id + "-flights." +
                                                      (geojson ? "geojson" : "csv") + "\"");
  res.stream = flight_export_stream(ds, q, std::move(plan), format);
  return res;
}

}  // namespace trailscope::server::handlers
