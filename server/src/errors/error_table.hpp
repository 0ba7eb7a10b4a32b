#pragma once
// The one table from exceptions to HTTP statuses, and the one error body:
//   {"error": "<kind>", "detail": "<message naming the parameter>", "param": "<name or empty>"}
#include <exception>
#include <string>

#include "routes/http_types.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::server {

/// HTTP status of an error kind: invalid_argument 400, not_found 404, conflict 409, payload_too_large 413,
/// unsupported_format 415, unprocessable 422, cancelled 409, backend and internal 500.
int http_status(Error::Kind kind) noexcept;

/// The response for any exception: trailscope::Error by its kind, nlohmann::json parse errors as 400
/// (param "body"), std::bad_alloc as 507, anything else as 500 (logged, with a generic detail).
Response error_response(const std::exception& e);
Response error_response(int status, const std::string& error, const std::string& param,
                        const std::string& detail);

}  // namespace trailscope::server
