#include "routes/handlers.hpp"
#include "routes/ownership.hpp"
#include "params/json_fields.hpp"
#include "limits.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::server::handlers {

namespace {
/// Depth colours of a replay unless the request names another colormap.
constexpr char kDefaultColormap[] = "viridis";

}  // namespace

Response list_replays(App& app, const Request& req, const PathParams&) {
  reject_unknown_params(req, {});
  return Response::json(200, {{"replays", need(app.replays, "a data folder").list()}});
}

Response get_replay(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {});
  return Response::json(200, need(app.replays, "a data folder").get(p.at("replay"))->to_json());
}

Response delete_replay(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {});
  ReplayManager& replays = need(app.replays, "a data folder");
  const std::string id = p.at("replay");
  require_owner(req, "replay", "replay", id, replays.get(id)->owner());
  replays.remove(id);
  return Response::no_content();
}

Response create_replay(App& app, const Request& req, const PathParams&) {
  reject_unknown_params(req, {});
  const nlohmann::json j = parse_body_object(req.body, {"video", "params", "colormap"});
  const std::string video = string_field(j, "video");
  const tracker::TrackerParams params = parse_tracker_params(j.value("params", nlohmann::json()));
  const std::string colormap = j.contains("colormap") ? string_field(j, "colormap") : kDefaultColormap;
  const auto replay = need(app.replays, "a data folder").create(video, params, colormap, req.principal.owner);
  return Response::json_at(201, replay->to_json(), "/api/v1/replays/" + replay->id());
}

Response replay_viewer_check(App& app, const Request&, const PathParams& p) {
  const std::string id = p.at("replay");
  // A server without a data folder has no replays: every replay is unknown.
  if (!app.replays) throw not_found("replay", "replay '" + id + "' does not exist");
  if (!app.replays->get(id)->has_room())
    throw Error(Error::Kind::conflict, "replay",
                "replay '" + id + "' has its limit of " + std::to_string(limits::kMaxReplayViewers) +
                    " viewers (kMaxReplayViewers)");
  return Response::status_only(101);
}

}  // namespace trailscope::server::handlers
