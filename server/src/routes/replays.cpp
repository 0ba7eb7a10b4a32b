#include "routes/handlers.hpp"
#include "routes/tracker_body.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::server::handlers {

namespace {
/// Depth colours of a replay unless the request names another colormap.
constexpr char kDefaultColormap[] = "viridis";

ReplayManager& replay_manager(App& app) {
  if (!app.replays) throw Error(Error::Kind::internal, "", "this server was started without a data folder");
  return *app.replays;
}
}  // namespace

Response list_replays(App& app, const Request& req, const PathParams&) {
  reject_unknown_params(req, {});
  return Response::json(200, {{"replays", replay_manager(app).list()}});
}

Response get_replay(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {});
  return Response::json(200, replay_manager(app).get(p.at("replay"))->to_json());
}

Response delete_replay(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {});
  replay_manager(app).remove(p.at("replay"));
  return Response::no_content();
}

Response create_replay(App& app, const Request& req, const PathParams&) {
  reject_unknown_params(req, {});
  const nlohmann::json j = parse_body_object(req.body, {"video", "params", "colormap"});
  const std::string video = string_field(j, "video");
  const tracker::TrackerParams params = parse_tracker_params(j.value("params", nlohmann::json()));
  const std::string colormap = j.contains("colormap") ? string_field(j, "colormap") : kDefaultColormap;
  const auto replay = replay_manager(app).create(video, params, colormap);
  Response res = Response::json(201, replay->to_json());
  res.headers.emplace_back("Location", "/api/v1/replays/" + replay->id());
  return res;
}

}  // namespace trailscope::server::handlers
