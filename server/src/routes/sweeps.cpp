// Parameter sweeps: the tracker over every point of a grid or random sample of parameter space on one or
// more stored videos, in one job; each run goes to the run store tagged with the sweep's id.
#include "routes/handlers.hpp"
#include "routes/tracker_body.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/tracker/sweep.hpp"
#include "trailscope/tracker/tracker_log.hpp"

namespace trailscope::server::handlers {
namespace fs = std::filesystem;

namespace {
SweepStore& sweep_store(App& app) {
  if (!app.sweeps || !app.runs || !app.videos)
    throw Error(Error::Kind::internal, "", "this server was started without run and video stores");
  return *app.sweeps;
}
}  // namespace

Response list_sweeps(App& app, const Request& req, const PathParams&) {
  reject_unknown_params(req, {});
  return Response::json(200, {{"sweeps", sweep_store(app).list()}});
}

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
  std::vector<std::string> videos;
  std::vector<fs::path> packs;
  for (const auto& id : *v) {
    if (!id.is_string()) throw invalid_argument("videos", "videos: must be a non-empty array of video ids");
    videos.push_back(id.get<std::string>());
    packs.push_back(app.videos->pack_path(videos.back()));  // 404 "video"
    const auto frames = app.videos->meta(videos.back()).at("frame_count").get<std::int64_t>();
    if (first >= frames)
      throw invalid_argument("first_frame", "first_frame: " + std::to_string(first) +
                                                " is not a frame of video '" + videos.back() + "' (it has " +
                                                std::to_string(frames) + ")");
    if (first + count > frames)
      throw invalid_argument("frame_count", "frame_count: " + std::to_string(count) + " frames from frame " +
                                                std::to_string(first) + " run past video '" + videos.back() +
                                                "' (" + std::to_string(frames) + " frames)");
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
  const std::string id =
      sweeps.create(tracker::to_json(spec), *v, {{"first_frame", first}, {"frame_count", count}}, total);
  const auto runs = app.runs;
  const auto store = app.sweeps;
  const JobState job = app.jobs.submit(
      "sweep", id,
      [runs, store, id, videos, packs, points, total, first, count](const ProgressFn& progress,
                                                                    const CancelToken& cancel) {
        std::size_t done = 0;
        try {
          for (const auto& params : points)
            for (std::size_t k = 0; k < videos.size(); ++k) {
              cancel.throw_if_cancelled();
              tracker::RunOptions ro;
              ro.video_id = videos[k];
              ro.first_frame = static_cast<std::size_t>(first);
              ro.frame_count = static_cast<std::size_t>(count);
              const ProgressFn report = [&](double f, std::string_view) {
                cancel.throw_if_cancelled();  // run_tracker stops at the throw; that run is not stored
                progress((static_cast<double>(done) + f) / static_cast<double>(total), "sweep");
              };
              const nlohmann::json row =
                  runs->put(tracker::run_tracker(packs[k], params, ro, report), "sweep", id);
              store->add_run(id, row.at("id").get<std::string>());
              progress(static_cast<double>(++done) / static_cast<double>(total), "sweep");
            }
        } catch (const Error& e) {
          store->finish(id, e.kind() == Error::Kind::cancelled ? "cancelled" : "failed");
          throw;
        } catch (...) {
          store->finish(id, "failed");
          throw;
        }
        store->finish(id, "done");
        return store->get(id);
      });
  sweeps.set_job(id, job.id);
  Response res = Response::json(202, {{"job", job.to_json()}, {"sweep", sweeps.get(id)}});
  res.headers.emplace_back("Location", "/api/v1/sweeps/" + id);
  return res;
}

}  // namespace trailscope::server::handlers
