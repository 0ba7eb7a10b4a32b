#include "trailscope/core/error.hpp"

namespace trailscope {

const char* to_string(Error::Kind kind) noexcept {
  switch (kind) {
    case Error::Kind::invalid_argument:
      return "invalid_argument";
    case Error::Kind::not_found:
      return "not_found";
    case Error::Kind::conflict:
      return "conflict";
    case Error::Kind::payload_too_large:
      return "payload_too_large";
    case Error::Kind::unsupported_format:
      return "unsupported_format";
    case Error::Kind::unprocessable:
      return "unprocessable";
    case Error::Kind::cancelled:
      return "cancelled";
    case Error::Kind::backend:
      return "backend_unavailable";
    case Error::Kind::internal:
      return "internal";
    case Error::Kind::unauthorized:
      return "unauthorized";
    case Error::Kind::forbidden:
      return "forbidden";
    case Error::Kind::request_timeout:
      return "request_timeout";
    case Error::Kind::too_many_requests:
      return "too_many_requests";
    case Error::Kind::unavailable:
      return "unavailable";
    case Error::Kind::insufficient_storage:
      return "insufficient_storage";
  }
  return "internal";
}

}  // namespace trailscope
