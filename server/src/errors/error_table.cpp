#include "errors/error_table.hpp"

#include <iostream>
#include <new>

namespace trailscope::server {

int http_status(Error::Kind kind) noexcept {
  switch (kind) {
    case Error::Kind::invalid_argument:
      return 400;
    case Error::Kind::not_found:
      return 404;
    case Error::Kind::conflict:
      return 409;
    case Error::Kind::payload_too_large:
      return 413;
    case Error::Kind::unsupported_format:
      return 415;
    case Error::Kind::unprocessable:
      return 422;
    case Error::Kind::cancelled:
      return 409;
    case Error::Kind::backend:
      return 500;
    case Error::Kind::internal:
      return 500;
    case Error::Kind::unauthorized:
      return 401;
    case Error::Kind::forbidden:
      return 403;
    case Error::Kind::request_timeout:
      return 408;
    case Error::Kind::too_many_requests:
      return 429;
    case Error::Kind::unavailable:
      return 503;
    case Error::Kind::insufficient_storage:
      return 507;
  }
  return 500;
}

nlohmann::json error_json(const std::string& error, const std::string& param, const std::string& detail) {
  return {{"error", error}, {"detail", detail}, {"param", param}};
}

Response error_response(int status, const std::string& error, const std::string& param,
                        const std::string& detail) {
  return Response::json(status, error_json(error, param, detail));
}

ErrorBody error_body(const std::exception& e) {
  if (const auto* te = dynamic_cast<const Error*>(&e)) {
    const int status = http_status(te->kind());
    if (status >= 500) std::cerr << "error: " << te->what() << "\n";
    return {status, error_json(to_string(te->kind()), te->param(), te->what())};
  }
  if (const auto* je = dynamic_cast<const nlohmann::json::exception*>(&e))
    return {400, error_json("invalid_argument", "body", std::string("malformed JSON: ") + je->what())};
  if (dynamic_cast<const std::bad_alloc*>(&e))
    return {507, error_json("insufficient_storage", "", "the server ran out of memory for this request")};
  // Only 5xx are logged: they are the server's fault, 4xx are the client's.
  std::cerr << "internal error: " << e.what() << "\n";
  return {500, error_json("internal", "", "internal server error")};
}

Response error_response(const std::exception& e) {
  ErrorBody b = error_body(e);
  Response res = Response::json(b.status, std::move(b.body));
  if (const auto* later = dynamic_cast<const RetryLater*>(&e))
    res.headers.emplace_back("Retry-After", std::to_string(later->retry_after_seconds()));
  if (b.status == 401) res.headers.emplace_back("WWW-Authenticate", "Bearer realm=\"trailscope\"");
  return res;
}

}  // namespace trailscope::server
