#pragma once
// The one table from exceptions to HTTP statuses, and the one error body:
//   {"error": "<kind>", "detail": "<message naming the parameter>", "param": "<name or empty>"}
#include <exception>
#include <string>

#include <nlohmann/json.hpp>

#include "routes/http_types.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::server {

/// HTTP status of an error kind: invalid_argument 400, unauthorized 401, forbidden 403, not_found 404,
/// request_timeout 408, conflict 409, payload_too_large 413, unsupported_format 415, unprocessable 422,
/// too_many_requests 429, cancelled 409, backend and internal 500, unavailable 503, insufficient_storage 507.
int http_status(Error::Kind kind) noexcept;

/// A refusal the client may retry later (too_many_requests, unavailable): its response carries
/// `Retry-After: <seconds>`.
class RetryLater : public Error {
 public:
  RetryLater(Kind kind, std::string param, const std::string& detail, int retry_after_seconds)
      : Error(kind, std::move(param), detail), retry_after_(retry_after_seconds) {}
  int retry_after_seconds() const noexcept { return retry_after_; }

 private:
  int retry_after_;
};

/// The error body {"error", "detail", "param"}.
nlohmann::json error_json(const std::string& error, const std::string& param, const std::string& detail);

/// An exception as its HTTP status and error body: trailscope::Error by its kind, nlohmann::json parse
/// errors as 400 (param "body"), std::bad_alloc as 507, anything else as 500 (logged, with a generic
/// detail). What a failed job or replay records as its "error", and what error_response sends.
struct ErrorBody {
  int status = 500;
  nlohmann::json body;
};
ErrorBody error_body(const std::exception& e);

/// The response for any exception: trailscope::Error by its kind, nlohmann::json parse errors as 400
/// (param "body"), std::bad_alloc as 507, anything else as 500 (logged, with a generic detail). A
/// RetryLater adds Retry-After; a 401 adds `WWW-Authenticate: Bearer`.
Response error_response(const std::exception& e);
Response error_response(int status, const std::string& error, const std::string& param,
                        const std::string& detail);

}  // namespace trailscope::server
