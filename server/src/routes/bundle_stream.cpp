// GET /api/v1/datasets/{dataset}/bundles/stream: the check before a bundle stream's WebSocket upgrade
// (the stream itself: bundle_stream/bundle_stream_session.hpp, proto/bundle_stream.md).
#include "routes/handlers.hpp"

namespace trailscope::server::handlers {

Response bundle_stream_check(App& app, const Request& req, const PathParams& p) {
  // Everything a stream needs comes in its control messages, so a query parameter is a mistake.
  reject_unknown_params(req, {});
  need(app.bundle_streams, "bundle streams").check(p.at("dataset"));
  return Response::status_only(101);
}

}  // namespace trailscope::server::handlers
