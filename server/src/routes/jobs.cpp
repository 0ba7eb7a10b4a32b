#include "routes/handlers.hpp"

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
  return Response::json(200, app.jobs.cancel(p.at("job")).to_json());
}

}  // namespace trailscope::server::handlers
