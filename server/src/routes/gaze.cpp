// Stored gaze datasets (store/gaze_store.hpp): upload (an ingest job), list, describe, delete; events and
// scanpaths under the shared gaze filters (params/gaze_filters.hpp, gaze/query.hpp); stimulus images.
#include <cmath>

#include "jobs/gaze_ingest_job.hpp"
#include "limits.hpp"
#include "params/gaze_filters.hpp"
#include "params/query_params.hpp"
#include "params/upload_body.hpp"
#include "routes/handlers.hpp"
#include "routes/ownership.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"
#include "trailscope/gaze/query.hpp"
#include "trailscope/gaze/stimulus.hpp"

namespace trailscope::server::handlers {
namespace {

GazeStore& gaze_store(App& app) {
  return need(app.gaze, "a gaze store");
}

/// The parameters of a gaze upload, checked (a taken name or a full store is 409): what the precheck
/// runs on the header and the handler again once the body is there.
GazeIngestRequest gaze_upload(App& app, const Request& req) {
  reject_unknown_params(req, {"name", "format", "participant", "stimulus", "eye", "width_px", "height_px",
                              "width_cm", "height_cm", "distance_cm"});
  auto it = req.query.find("name");
  if (it == req.query.end() || it->second.empty())
    throw invalid_argument("name", "name: the gaze dataset name is required (?name=...)");
  GazeIngestRequest ing;
  ing.name = it->second;
  gaze_store(app).check_new(ing.name);
  if (auto f = req.query.find("format"); f != req.query.end() && f->second != "auto")
    ing.options.format = gaze::parse_gaze_format(f->second, "format");
  ing.options.participant = params::text(req, "participant", "");
  ing.options.stimulus = params::text(req, "stimulus", "");
  ing.options.eye = gaze::parse_eye(params::text(req, "eye", "average"), "eye");
  gaze::ScreenGeometry& g = ing.options.geometry;
  for (auto [name, field] : {std::pair{"width_px", &g.width_px}, std::pair{"height_px", &g.height_px},
                             std::pair{"width_cm", &g.width_cm}, std::pair{"height_cm", &g.height_cm},
                             std::pair{"distance_cm", &g.distance_cm}}) {
    *field = params::number(req, name, 0);
    if (req.query.count(name) && !(*field > 0 && *field <= 1e6))
      throw invalid_argument(name, std::string(name) + " must be in (0, 1000000], got " + req.query.at(name));
  }
  ing.owner = req.principal.owner;
  app.jobs.check_quota(ing.owner);
  return ing;
}

/// `stimulus` of the request, or the dataset's only stimulus when it has one and the request names none.
std::string stimulus_param(const Request& req, const nlohmann::json& meta) {
  if (auto it = req.query.find("stimulus"); it != req.query.end()) return it->second;
  const auto& stimuli = meta.at("stimuli");
  if (stimuli.size() == 1) return stimuli.front().get<std::string>();
  throw invalid_argument("stimulus", "stimulus: the dataset has " + std::to_string(stimuli.size()) +
                                         " stimuli, say which (?stimulus=...): " + stimuli.dump());
}

nlohmann::json counts_json(const gaze::EventList& ev, const std::vector<gaze::EventType>& types) {
  nlohmann::json counts = nlohmann::json::object();
  for (gaze::EventType t : {gaze::EventType::fixation, gaze::EventType::saccade, gaze::EventType::pso,
                            gaze::EventType::pursuit, gaze::EventType::blink, gaze::EventType::undefined})
    if (types.empty() || std::find(types.begin(), types.end(), t) != types.end())
      counts[gaze::to_string(t)] = ev.counts[std::size_t(t)];
  return counts;
}
}  // namespace

void create_gaze_check(App& app, const Request& req, const PathParams&) {
  gaze_upload(app, req);
}

Response create_gaze(App& app, const Request& req, const PathParams&) {
  GazeIngestRequest ing = gaze_upload(app, req);
  ing.file = upload_file(req, app.upload_dir);
  const JobState job = submit_gaze_ingest(app.jobs, app.gaze, std::move(ing), app.disk);
  return Response::json_at(202, {{"job", job.to_json()}}, "/api/v1/jobs/" + job.id);
}

Response list_gaze(App& app, const Request& req, const PathParams&) {
  reject_unknown_params(req, {});
  nlohmann::json list = nlohmann::json::array();
  for (auto& m : gaze_store(app).list()) list.push_back(std::move(m));
  return Response::json(200, {{"datasets", std::move(list)}});
}

Response get_gaze(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {});
  return Response::json(200, gaze_store(app).meta(p.at("gaze")));
}

Response delete_gaze(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {});
  const std::string id = p.at("gaze");
  GazeStore& store = gaze_store(app);
  require_owner(req, "gaze", "gaze dataset", id, store.owner(id));  // after owner()'s 404
  store.remove(id);
  return Response::no_content();
}

Response gaze_events(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, params::with_gaze_filter_keys({"type"}));
  const params::GazeFilters f = params::parse_gaze_filters(req);
  std::vector<gaze::EventType> types;
  if (auto it = req.query.find("type"); it != req.query.end()) {
    std::string_view rest = it->second;
    while (true) {
      const auto comma = rest.find(',');
      types.push_back(gaze::parse_event_type(rest.substr(0, comma), "type"));
      if (comma == std::string_view::npos) break;
      rest.remove_prefix(comma + 1);
    }
  }
  const auto ds = gaze_store(app).get(p.at("gaze"));
  const gaze::EventList ev = gaze::list_events(*ds, f.select, f.events, types, limits::kMaxGazeEvents);
  nlohmann::json events = nlohmann::json::array();
  for (const gaze::EventRow& e : ev.events)
    events.push_back({{"recording", e.recording},
                      {"type", gaze::to_string(e.type)},
                      {"t_start_ms", e.t_start_ms},
                      {"t_end_ms", e.t_end_ms},
                      {"duration_ms", e.t_end_ms - e.t_start_ms},
                      {"x", number_or_null(e.x)},
                      {"y", number_or_null(e.y)},
                      {"x_end", number_or_null(e.x_end)},
                      {"y_end", number_or_null(e.y_end)}});
  return Response::json(200, {{"events", std::move(events)},
                              {"counts", counts_json(ev, types)},
                              {"method", gaze::to_string(f.events.method)}});
}

Response gaze_scanpaths(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, params::gaze_filter_keys());
  const params::GazeFilters f = params::parse_gaze_filters(req);
  const auto ds = gaze_store(app).get(p.at("gaze"));
  nlohmann::json out = nlohmann::json::array();
  for (const gaze::Scanpath& s : gaze::scanpaths(*ds, f.select, f.events, limits::kMaxGazeEvents)) {
    nlohmann::json fix = nlohmann::json::array();
    for (const gaze::ScanpathFixation& x : s.fixations)
      fix.push_back({{"x", number_or_null(x.x)},
                     {"y", number_or_null(x.y)},
                     {"t_start_ms", x.t_start_ms},
                     {"duration_ms", x.duration_ms}});
    out.push_back({{"recording", s.recording},
                   {"participant", s.participant},
                   {"stimulus", s.stimulus},
                   {"fixations", std::move(fix)}});
  }
  return Response::json(200, {{"scanpaths", std::move(out)}, {"method", gaze::to_string(f.events.method)}});
}

Response put_gaze_stimulus(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {"stimulus"});
  const std::string id = p.at("gaze");
  GazeStore& store = gaze_store(app);
  const nlohmann::json meta = store.meta(id);
  require_owner(req, "gaze", "gaze dataset", id, meta.value("owner", ""), "change");
  const std::string stimulus = stimulus_param(req, meta);
  const std::string bytes = upload_bytes(req, limits::kMaxGazeStimulusBytes,
                                         "the stimulus image is larger than kMaxGazeStimulusBytes (" +
                                             std::to_string(limits::kMaxGazeStimulusBytes) + " bytes)");
  const gaze::StimulusImage image = gaze::inspect_stimulus_image(bytes, limits::kMaxGazeStimulusPixels);
  return Response::json(200, store.put_stimulus(id, stimulus, bytes, image));
}

Response get_gaze_stimulus(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {"stimulus"});
  GazeStore& store = gaze_store(app);
  const std::string id = p.at("gaze");
  GazeStore::Image image = store.stimulus(id, stimulus_param(req, store.meta(id)));
  Response res;
  res.content_type = std::move(image.content_type);
  res.body = std::move(image.bytes);
  return res;
}

}  // namespace trailscope::server::handlers
