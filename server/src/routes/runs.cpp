#include "jobs/track_job.hpp"
#include "routes/handlers.hpp"
#include "params/query_params.hpp"
#include "params/json_fields.hpp"
#include "params/upload_body.hpp"
#include "trailscope/core/error.hpp"
#include "limits.hpp"
#include "trailscope/tof/depth_render.hpp"
#include "trailscope/tracker/params.hpp"

namespace trailscope::server::handlers {
namespace fs = std::filesystem;

namespace {
const std::string kTooLarge =
    "run upload exceeds the limit of " + std::to_string(limits::kMaxRunBytes >> 20) + " MiB";

}  // namespace

Response tracker_params(App&, const Request& req, const PathParams&) {
  reject_unknown_params(req, {});
  nlohmann::json list = nlohmann::json::array();
  for (const auto& i : tracker::parameter_infos())
    list.push_back({{"name", i.name},
                    {"unit", i.unit},
                    {"default", i.default_number},
                    {"min", i.min},
                    {"max", i.max},
                    {"integer", i.integer},
                    {"help", i.help}});
  return Response::json(
      200, {{"params", std::move(list)}, {"tracker_version", std::string(tracker::kTrackerVersion)}});
}

Response get_run(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {});
  RunStore& runs = need(app.runs, "a run store");
  nlohmann::json j = runs.meta(p.at("run"));
  j["header"] = tracker::header_to_json(runs.get(p.at("run"))->header);
  return Response::json(200, j);
}

// A run upload takes no parameters and needs room in the run store (409 when full): checked on the header
// and again by the handler.
void create_run_check(App& app, const Request& req, const PathParams&) {
  reject_unknown_params(req, {});
  need(app.runs, "a run store").check_room();
}

Response create_run(App& app, const Request& req, const PathParams& p) {
  create_run_check(app, req, p);
  RunStore& runs = *app.runs;
  const std::string bytes = upload_bytes(req, limits::kMaxRunBytes, kTooLarge);
  const nlohmann::json row = runs.put(tracker::decode_log(bytes), "upload", "", req.principal.owner);
  return Response::json_at(201, row, "/api/v1/runs/" + row.at("id").get<std::string>());
}

Response track_run(App& app, const Request& req, const PathParams&) {
  reject_unknown_params(req, {});
  const nlohmann::json j = parse_body_object(req.body, {"video", "params"});
  const std::string video = string_field(j, "video");
  const tracker::TrackerParams params = parse_tracker_params(j.value("params", nlohmann::json()));
  need(app.videos, "a video store");
  const fs::path pack = app.videos->pack_path(video);
  need(app.runs, "a run store").check_room();
  const JobState job = submit_track(app.jobs, app.runs, pack, params, video, req.principal.owner);
  return Response::json_at(202, {{"job", job.to_json()}}, "/api/v1/jobs/" + job.id);
}

Response run_log(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {"format"});
  const auto it = req.query.find("format");
  const std::string format = it == req.query.end() ? "json" : it->second;
  if (format != "json" && format != "binary")
    throw invalid_argument("format", "format must be json or binary, got '" + format + "'");
  RunStore& runs = need(app.runs, "a run store");
  Response res;
  if (format == "binary") {
    res.content_type = "application/x-protobuf";
    res.body = read_whole_file(runs.log_path(p.at("run")));
  } else {
    res.body = tracker::encode_log(*runs.get(p.at("run")), tracker::LogEncoding::json);
  }
  return res;
}

Response run_frames(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {"from", "to"});
  const std::string id = p.at("run");
  const auto log = need(app.runs, "a run store").get(id);
  const auto total = static_cast<std::int64_t>(log->frames.size());
  const std::int64_t from = params::integer(req, "from", 0, 0, total);
  const std::int64_t to = params::integer(
      req, "to",
      std::min<std::int64_t>(total, from + static_cast<std::int64_t>(limits::kDefaultRunFramesPerPage)), from,
      total);
  if (to - from > static_cast<std::int64_t>(limits::kMaxRunFramesPerPage))
    throw invalid_argument("to", "to - from must be at most " + std::to_string(limits::kMaxRunFramesPerPage) +
                                     " frames per page (kMaxRunFramesPerPage), got " +
                                     std::to_string(to - from));
  nlohmann::json frames = nlohmann::json::array(), truth = nlohmann::json::array();
  for (std::int64_t i = from; i < to; ++i) {
    const auto k = static_cast<std::size_t>(i);
    frames.push_back(tracker::frame_to_json(log->frames[k]));
    if (!log->truth.empty())
      truth.push_back(log->truth[k] ? tof::truth_to_json(*log->truth[k]) : nlohmann::json(nullptr));
  }
  return Response::json(200, {{"run", id},
                              {"from", from},
                              {"to", to},
                              {"total", total},
                              {"frames", std::move(frames)},
                              {"truth", log->truth.empty() ? nlohmann::json(nullptr) : std::move(truth)}});
}

}  // namespace trailscope::server::handlers
