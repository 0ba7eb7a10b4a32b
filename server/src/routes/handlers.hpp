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

Response static_file(App& app, const Request& req, const PathParams& p);

}  // namespace trailscope::server::handlers
