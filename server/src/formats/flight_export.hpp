#pragma once
// The streamed export of a window's flights (GET .../export, `trailscope export`): GeoJSON or CSV text
// produced a piece at a time from a plan checked beforehand (compute/.../trails/export.hpp), so neither
// the server nor the CLI ever holds a whole export in memory.
//
// GeoJSON: {"type":"FeatureCollection","dataset":ID,"query":CANONICAL,"flights":N,"points":P,
// "features":[...]} with one flight_geojson(set, id, q, clip = true) Feature per planned flight, in
// ascending id. CSV: flights_csv_header(), then append_flight_csv() per planned flight.
#include <functional>
#include <memory>
#include <string>

#include "store/dataset_store.hpp"
#include "trailscope/trails/export.hpp"

namespace trailscope::server {

enum class FlightExportFormat { geojson, csv };

/// Parses "geojson" | "csv"; throws invalid_argument(param, "<param> must be 'geojson' or 'csv', got
/// '<text>'") otherwise.
FlightExportFormat parse_flight_export_format(const std::string& text, const std::string& param = "format");

/// A producer for Response::stream: each call appends the next piece (whole flights up to about
/// limits::kExportPieceBytes) and returns false after the last. Keeps `ds` alive.
std::function<bool(std::string&)> flight_export_stream(std::shared_ptr<const Dataset> ds, const Query& q,
                                                       ExportPlan plan, FlightExportFormat format);

}  // namespace trailscope::server
