#include <chrono>

#include "routes/handlers.hpp"
#include "routes/ownership.hpp"
#include "params/query_params.hpp"
#include "params/upload_body.hpp"
#include "params/tile_params.hpp"
#include "jobs/ingest_job.hpp"
#include "trailscope/core/error.hpp"
#include "limits.hpp"
#include "trailscope/ingest/format.hpp"
#include "store/dataset_reads.hpp"
#include "trailscope/trails/summary.hpp"

namespace trailscope::server::handlers {
namespace fs = std::filesystem;

Response list_datasets(App& app, const Request& req, const PathParams&) {
  reject_unknown_params(req, {});
  nlohmann::json list = nlohmann::json::array();
  for (const auto& ds : app.store->list()) list.push_back(ds->to_json());
  return Response::json(200, {{"datasets", std::move(list)}});
}

Response get_dataset(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {});
  return Response::json(200, app.store->describe(p.at("dataset"))->to_json());
}

Response delete_dataset(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {});
  const std::string id = p.at("dataset");
  require_owner(req, "dataset", "dataset", id, app.store->describe(id)->owner);  // after describe's 404
  app.store->remove(id);
  app.tiles.erase_prefix(params::dataset_cache_prefix(id));
  app.animation_chunks.erase_prefix(params::dataset_cache_prefix(id));
  app.flow_maps.erase_prefix(params::dataset_cache_prefix(id));
  return Response::no_content();
}

namespace {
// The parameters of a dataset upload, checked (a taken name is 409): what the precheck runs on the header
// and the handler again once the body is there.
IngestRequest dataset_upload(App& app, const Request& req) {
  reject_unknown_params(req, {"name", "format", "split_jumps"});
  auto it = req.query.find("name");
  if (it == req.query.end() || it->second.empty())
    throw invalid_argument("name", "name: the dataset name is required (?name=...)");
  IngestRequest ing;
  ing.name = it->second;
  validate_dataset_id(ing.name, "name");
  if (auto f = req.query.find("format"); f != req.query.end() && f->second != "auto") {
    ingest::parse_format(f->second, "format");  // fail now, not in the job
    ing.format = f->second;
  }
  if (auto s = req.query.find("split_jumps"); s != req.query.end()) {
    if (s->second != "true" && s->second != "false")
      throw invalid_argument("split_jumps", "split_jumps must be 'true' or 'false', got '" + s->second + "'");
    ing.split_jumps = s->second == "true";
  }
  if (app.store->contains(ing.name))
    throw Error(Error::Kind::conflict, "name", "dataset '" + ing.name + "' already exists");
  ing.owner = req.principal.owner;
  app.jobs.check_quota(ing.owner);
  return ing;
}
}  // namespace

void create_dataset_check(App& app, const Request& req, const PathParams&) {
  dataset_upload(app, req);
}

Response create_dataset(App& app, const Request& req, const PathParams&) {
  IngestRequest ing = dataset_upload(app, req);
  ing.file = upload_file(req, app.upload_dir);
  const JobState job = submit_ingest(app.jobs, app.store, std::move(ing), app.disk);
  return Response::json_at(202, {{"job", job.to_json()}}, "/api/v1/jobs/" + job.id);
}

Response summary(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, params::with_query_keys({"bins", "top", "format", "table"}));
  const auto ds = app.store->describe(p.at("dataset"));
  const Query q = parse_query(req.query);
  SummaryOptions opts;
  opts.bins = static_cast<int>(params::integer(req, "bins", opts.bins, 1, limits::kMaxHistogramBins));
  opts.top_callsigns =
      static_cast<int>(params::integer(req, "top", opts.top_callsigns, 0, limits::kMaxTopCallsigns));
  if (auto u = req.query.find("alt_unit"); u != req.query.end() && u->second == "m")
    opts.alt_unit = AltUnit::m;
  const std::string format = params::text(req, "format", "json");
  if (format != "json" && format != "csv")
    throw invalid_argument("format", "format must be 'json' or 'csv', got '" + format + "'");
  const std::string table = params::text(req, "table", "totals");
  if (format == "json" && req.query.count("table"))
    throw invalid_argument("table", "table applies to format=csv only (the JSON holds every table)");
  if (format == "csv") {
    (void)Summary{}.to_csv(table);  // an unknown table is refused before the work
    const Summary s = reads_of(*app.store).summarize(*ds, q, opts);
    Response res;
    res.content_type = "text/csv; charset=utf-8";
    res.body = s.to_csv(table);
    res.headers.emplace_back("Content-Disposition",
                             "attachment; filename=\"" + ds->id + "-summary-" + table + ".csv\"");
    return res;
  }
  const auto start = std::chrono::steady_clock::now();
  nlohmann::json j = reads_of(*app.store).summarize(*ds, q, opts).to_json();
  j["dataset"] = ds->id;
  j["query"] = q.canonical();
  j["elapsed_ms"] =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return Response::json(200, j);
}

Response list_flights(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, params::with_query_keys({"page", "page_size", "sort", "order"}));
  const auto ds = app.store->describe(p.at("dataset"));
  const Query q = parse_query(req.query);
  const auto page = params::integer(req, "page", 0, 0, 1'000'000'000);
  const auto size = params::integer(req, "page_size", limits::kDefaultPageSize, 1, limits::kMaxPageSize);
  const FlightSort sort =
      parse_flight_sort(params::text(req, "sort", "t_start"), params::text(req, "order", "asc"));
  return Response::json(200, reads_of(*app.store).list_flights(*ds, q, page, size, sort).to_json());
}

Response get_flight(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, params::with_query_keys({"clip", "max_points"}));
  const auto ds = app.store->get(p.at("dataset"));
  const auto id = params::path_integer(p, "flight_id", 0, 0xffffffffLL);
  const Query q = parse_query(req.query);
  const bool clip = params::integer(req, "clip", 0, 0, 1) == 1;
  const auto max_points =
      params::integer(req, "max_points", limits::kMaxPointsPerResponse, 1, limits::kMaxPointsPerResponse);
  Response res = Response::json(200, flight_geojson(*ds->trails, id, q, clip, max_points));
  res.content_type = "application/geo+json";
  return res;
}

}  // namespace trailscope::server::handlers
