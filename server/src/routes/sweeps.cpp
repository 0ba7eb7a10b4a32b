// Parameter sweeps: the tracker over every point of a grid or random sample of parameter space on one or
// more stored videos, in one job (jobs/sweep_job.hpp); each run goes to the run store tagged with the
// sweep's id.
#include "jobs/sweep_job.hpp"
#include "routes/handlers.hpp"
#include "params/json_fields.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/tracker/sweep.hpp"

namespace trailscope::server::handlers {

namespace {
SweepStore& sweep_store(App& app) {
  if (!app.sweeps || !app.runs || !app.videos)
    throw Error(Error::Kind::internal, "", "this server was started without run and video stores");
  return *app.sweeps;
}
}  // namespace

Response get_sweep(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {});
  SweepStore& sweeps = sweep_store(app);
  const std::string id = p.at("sweep");
  nlohmann::json r = sweeps.get(id);
  // A job cancelled while still queued never ran its work, which ends the sweep: end it here.
  if (r.at("state") == "running" && r.at("job").is_string()) {
    std::string state;
    for (const JobState& job : app.jobs.list())
      if (job.id == r.at("job")) state = job.state;
    if (state == "cancelled" || state == "failed") {
      sweeps.finish(id, state);
      r = sweeps.get(id);
    }
  }
  return Response::json(200, r);
}

Response create_sweep(App& app, const Request& req, const PathParams&) {
  reject_unknown_params(req, {});
  SweepStore& sweeps = sweep_store(app);
  const nlohmann::json j = parse_body_object(req.body, {"videos", "sweep", "first_frame", "frame_count"});
  // The frame range tracked in every video (a short range makes a quick sweep); checked against each video
  // now, so that the job does not fail at its first run.
  const std::int64_t first = integer_field(j, "first_frame", 0), count = integer_field(j, "frame_count", 0);
  if (first < 0) throw invalid_argument("first_frame", "first_frame: must be ≥ 0");
  if (count < 0) throw invalid_argument("frame_count", "frame_count: must be ≥ 0 (0 = to the end)");
  const auto v = j.find("videos");
  if (v == j.end() || !v->is_array() || v->empty())
    throw invalid_argument("videos", "videos: must be a non-empty array of video ids");
  std::vector<tracker::SweepVideo> videos;
  for (const auto& id : *v) {
    if (!id.is_string()) throw invalid_argument("videos", "videos: must be a non-empty array of video ids");
    const std::string video = id.get<std::string>();
    videos.push_back({video, app.videos->pack_path(video)});  // 404 "video"
    const auto frames = app.videos->meta(video).at("frame_count").get<std::int64_t>();
    if (first >= frames)
      throw invalid_argument("first_frame", "first_frame: " + std::to_string(first) +
                                                " is not a frame of video '" + video + "' (it has " +
                                                std::to_string(frames) + ")");
    if (first + count > frames)
      throw invalid_argument("frame_count", "frame_count: " + std::to_string(count) + " frames from frame " +
                                                std::to_string(first) + " run past video '" + video + "' (" +
                                                std::to_string(frames) + " frames)");
  }
  if (!j.contains("sweep")) throw invalid_argument("sweep", "sweep: required");
  const tracker::SweepSpec spec = tracker::parse_sweep(j["sweep"]);
  const std::vector<tracker::TrackerParams> points = tracker::sweep_points(spec);
  const std::size_t total = points.size() * videos.size();
  if (total > limits::kMaxSweepRuns)
    throw Error(Error::Kind::payload_too_large, "videos",
                std::to_string(points.size()) + " points x " + std::to_string(videos.size()) +
                    " videos = " + std::to_string(total) + " runs, more than the limit of " +
                    std::to_string(limits::kMaxSweepRuns) + " (kMaxSweepRuns)");
  app.runs->check_room(total);
  app.jobs.check_quota(req.principal.owner);  // before the sweep is recorded
  const std::string id =
      sweeps.create(tracker::to_json(spec), *v, {{"first_frame", first}, {"frame_count", count}}, total,
                    req.principal.owner);
  tracker::RunOptions range;
  range.first_frame = static_cast<std::size_t>(first);
  range.frame_count = static_cast<std::size_t>(count);
  const JobState job =
      submit_sweep(app.jobs, app.runs, app.sweeps, id, points, std::move(videos), range, req.principal.owner);
  return Response::json_at(202, {{"job", job.to_json()}, {"sweep", sweeps.get(id)}}, "/api/v1/sweeps/" + id);
}

}  // namespace trailscope::server::handlers
