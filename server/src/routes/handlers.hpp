#pragma once
// Route handlers, one file per resource. Each parses, calls compute/ or the store, and serialises.
#include "routes/app.hpp"

namespace trailscope::server::handlers {

Response health(App& app, const Request& req, const PathParams& p);

Response list_datasets(App& app, const Request& req, const PathParams& p);
Response create_dataset(App& app, const Request& req, const PathParams& p);
Response get_dataset(App& app, const Request& req, const PathParams& p);
Response delete_dataset(App& app, const Request& req, const PathParams& p);

Response summary(App& app, const Request& req, const PathParams& p);
Response list_flights(App& app, const Request& req, const PathParams& p);
Response get_flight(App& app, const Request& req, const PathParams& p);

Response list_jobs(App& app, const Request& req, const PathParams& p);
Response get_job(App& app, const Request& req, const PathParams& p);
Response cancel_job(App& app, const Request& req, const PathParams& p);

Response density_tile(App& app, const Request& req, const PathParams& p);

Response list_graphs(App& app, const Request& req, const PathParams& p);
Response create_graph(App& app, const Request& req, const PathParams& p);
Response get_graph(App& app, const Request& req, const PathParams& p);
Response delete_graph(App& app, const Request& req, const PathParams& p);

Response bundle_params(App& app, const Request& req, const PathParams& p);
Response list_bundles(App& app, const Request& req, const PathParams& p);
Response create_bundle(App& app, const Request& req, const PathParams& p);
Response get_bundle(App& app, const Request& req, const PathParams& p);
Response delete_bundle(App& app, const Request& req, const PathParams& p);
Response bundle_image(App& app, const Request& req, const PathParams& p);
Response bundle_polylines(App& app, const Request& req, const PathParams& p);
Response bundle_tile(App& app, const Request& req, const PathParams& p);

Response static_file(App& app, const Request& req, const PathParams& p);

}  // namespace trailscope::server::handlers
