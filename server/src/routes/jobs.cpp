#include "routes/handlers.hpp"
#include "routes/ownership.hpp"

namespace trailscope::server::handlers {

Response list_jobs(App& app, const Request& req, const PathParams&) {
  reject_unknown_params(req, {});
  nlohmann::json list = nlohmann::json::array();
  for (const auto& j : app.jobs.list()) list.push_back(j.to_json());
  return Response::json(200, {{"jobs", std::move(list)}});
}

Response get_job(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {});
  return Response::json(200, app.jobs.get(p.at("job")).to_json());
}

Response cancel_job(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {});
  const std::string id = p.at("job");
  require_owner(req, "job", "job", id, app.jobs.get(id).owner, "cancel");
  return Response::json(200, app.jobs.cancel(id).to_json());
}

}  // namespace trailscope::server::handlers
