// Airspace sectors (POST/GET/DELETE /api/v1/sectors) and congestion counts (POST /api/v1/congestion, a
// job; GET /api/v1/congestion/{job}, its result as JSON or CSV). The counts and their definitions are in
// compute/include/trailscope/congestion/; the job in jobs/congestion_job.hpp.
#include <algorithm>

#include "jobs/congestion_job.hpp"
#include "params/congestion_body.hpp"
#include "params/json_fields.hpp"
#include "params/query_params.hpp"
#include "params/upload_body.hpp"
#include "routes/handlers.hpp"
#include "trailscope/congestion/volumes.hpp"
#include "trailscope/core/error.hpp"
#include "limits.hpp"

namespace trailscope::server::handlers {

namespace {
/// Longest display name of a sector set (characters).
constexpr std::size_t kMaxSectorSetNameLength = 128;

const std::string kTooLarge =
    "sector upload exceeds the limit of " + std::to_string(limits::kMaxSectorUploadBytes >> 20) + " MiB";

/// The sectors of a GeoJSON text, checked by the one parser of sectors (congestion/volumes.hpp). Text
/// that is not JSON at all is a 400 on the body; JSON that is not a valid FeatureCollection of sectors is
/// the parser's 422 (or 413 above limits::kMaxSectors), naming "sectors".
std::vector<congestion::Sector> parse_sector_text(const std::string& text) {
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded())
    throw invalid_argument("body",
                           "body: not JSON (a GeoJSON FeatureCollection of Polygon features is expected)");
  return congestion::parse_sectors(j);
}

/// What the metadata of a stored set says about its sectors.
nlohmann::json sector_figures(const std::vector<congestion::Sector>& sectors) {
  nlohmann::json names = nlohmann::json::array();
  double west = 180, south = 90, east = -180, north = -90, lower = 999, upper = 0;
  std::size_t vertices = 0;
  for (const auto& s : sectors) {
    names.push_back(s.name);
    vertices += s.ring.size();
    for (const auto& [lon, lat] : s.ring)
      west = std::min(west, lon), east = std::max(east, lon), south = std::min(south, lat),
      north = std::max(north, lat);
    lower = std::min(lower, s.lower_fl), upper = std::max(upper, s.upper_fl);
  }
  return {{"sectors", sectors.size()},          {"vertices", vertices}, {"names", std::move(names)},
          {"bbox", {west, south, east, north}}, {"lower_fl", lower},    {"upper_fl", upper}};
}
}  // namespace

Response create_sectors(App& app, const Request& req, const PathParams&) {
  reject_unknown_params(req, {"name"});
  SectorStore& store = need(app.sectors, "a sector store");
  std::string name;
  if (auto n = req.query.find("name"); n != req.query.end()) {
    if (n->second.empty() || n->second.size() > kMaxSectorSetNameLength)
      throw invalid_argument("name", "name: 1 to " + std::to_string(kMaxSectorSetNameLength) + " characters");
    name = n->second;
  }
  const std::string text = upload_bytes(req, limits::kMaxSectorUploadBytes, kTooLarge);
  const nlohmann::json meta =
      store.put(name, text, sector_figures(parse_sector_text(text)), req.principal.owner);
  return Response::json_at(201, meta, "/api/v1/sectors/" + meta.at("id").get<std::string>());
}

Response get_sectors(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {});
  Response res;
  res.content_type = "application/geo+json";
  res.body = need(app.sectors, "a sector store").geojson(p.at("sectors"));
  return res;
}

Response create_congestion(App& app, const Request& req, const PathParams&) {
  reject_unknown_params(req, {});
  CongestionRequest r = parse_congestion_request(parse_json_object(req.body, "body: must be a JSON object"));
  // Everything a job would fail on is this request's error: an unknown dataset or sector set is a 404,
  // a sector set that no longer parses a 422, too many sectors a 413.
  const auto ds = app.store->get(r.dataset);
  if (!r.sectors.empty()) {
    r.counts.sectors = parse_sector_text(need(app.sectors, "a sector store").geojson(r.sectors));
    congestion::validate(r.counts);
  }
  const JobState job = submit_congestion(app.jobs, app.congestion, ds, std::move(r), req.principal.owner);
  return Response::json_at(202, {{"job", job.to_json()}, {"congestion", "/api/v1/congestion/" + job.id}},
                           "/api/v1/jobs/" + job.id);
}

Response get_congestion(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {"format", "table"});
  const std::string format = params::text(req, "format", "json");
  if (format != "json" && format != "csv")
    throw invalid_argument("format", "format must be json or csv, got '" + format + "'");
  if (format == "json" && req.query.count("table"))
    throw invalid_argument("table", "table: applies to format=csv (the JSON holds every table)");
  const std::string id = p.at("job");
  const JobState job = app.jobs.get(id);  // 404 "job"
  if (job.kind != "congestion")
    throw not_found("job", "job '" + id + "' is a " + job.kind + " job, not a congestion job");
  if (job.state != "done") {
    std::string detail = "job '" + id + "' is " + job.state;
    if (job.state == "failed" && job.error.contains("detail"))
      detail += ": " + job.error["detail"].get<std::string>();
    else if (job.state == "queued" || job.state == "running")
      detail += "; its result is not ready (GET /api/v1/jobs/" + id + " or the WebSocket shows its progress)";
    throw Error(Error::Kind::conflict, "job", detail);
  }
  const auto out = app.congestion->get(id);
  if (!out)
    throw not_found("job", "the result of congestion job '" + id +
                               "' is no longer kept (the server keeps the last " +
                               std::to_string(limits::kMaxCongestionResults) + ", kMaxCongestionResults)");
  if (format == "json") {
    nlohmann::json j = out->to_json();
    j["job"] = id;
    return Response::json(200, j);
  }
  Response res;
  res.content_type = "text/csv";
  res.body = out->csv(params::text(req, "table", "series"));
  return res;
}

}  // namespace trailscope::server::handlers
