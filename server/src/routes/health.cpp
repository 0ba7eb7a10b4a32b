#include "routes/handlers.hpp"
#include "trailscope/ocl_info.hpp"

namespace trailscope::server::handlers {

Response health(App& app, const Request&, const PathParams&) {
  const auto info = opencl_info();
  return Response::json(200, {{"status", "ok"},
                              {"version", TRAILSCOPE_VERSION},
                              {"datasets", app.store->list().size()},
                              {"opencl", {{"available", info.available}, {"device", info.device}}}});
}

}  // namespace trailscope::server::handlers
