#include "formats/flight_export.hpp"

#include "limits.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"
#include "trailscope/trails/summary.hpp"

namespace trailscope::server {

FlightExportFormat parse_flight_export_format(const std::string& text, const std::string& param) {
  if (text == "geojson") return FlightExportFormat::geojson;
  if (text == "csv") return FlightExportFormat::csv;
  throw invalid_argument(param, param + " must be 'geojson' or 'csv', got '" + text + "'");
}

namespace {
struct ExportStream {
  std::shared_ptr<const Dataset> ds;
  Query q;
  PointFilter filter;
  ExportPlan plan;
  bool geojson = false;
  std::size_t next = 0;  // the next flight of plan.flights
  bool opened = false;

  bool operator()(std::string& out) {
    if (!opened) {
      opened = true;
      if (geojson)
        out += "{\"type\":\"FeatureCollection\",\"dataset\":" + json_text(ds->id) +
               ",\"query\":" + json_text(q.canonical()) +
               ",\"flights\":" + std::to_string(plan.flights.size()) +
               ",\"points\":" + std::to_string(plan.points) + ",\"features\":[";
      else
        out += flights_csv_header();
    }
    const std::size_t start = out.size();
    while (next < plan.flights.size() && out.size() - start < limits::kExportPieceBytes) {
      const std::uint32_t id = plan.flights[next];
      if (geojson) {
        if (next > 0) out += ',';
        out += json_text(flight_geojson(*ds->trails, id, q, true, limits::kMaxExportPoints));
      } else {
        append_flight_csv(out, *ds->trails, filter, id);
      }
      ++next;
    }
    if (next < plan.flights.size()) return true;
    if (geojson) out += "]}";
    return false;
  }
};
}  // namespace

std::function<bool(std::string&)> flight_export_stream(std::shared_ptr<const Dataset> ds, const Query& q,
                                                       ExportPlan plan, FlightExportFormat format) {
  auto s = std::make_shared<ExportStream>(
      ExportStream{std::move(ds), q, PointFilter(q), std::move(plan), format == FlightExportFormat::geojson});
  return [s](std::string& out) { return (*s)(out); };
}

}  // namespace trailscope::server
