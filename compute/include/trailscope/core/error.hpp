#pragma once
// The one family of exceptions that compute/ throws. The server maps each Kind to an HTTP status in one
// table (server/src/errors/error_table.cpp); the CLI prints `what()` and exits non-zero.
#include <stdexcept>
#include <string>

namespace trailscope {

/// Base of every TrailScope error. `param()` names the offending parameter (or is empty) and is what the
/// HTTP error body reports, so a client can point at the field it must fix.
class Error : public std::runtime_error {
 public:
  enum class Kind {
    invalid_argument,    ///< a parameter is malformed or out of range (HTTP 400)
    not_found,           ///< a named resource does not exist (404)
    conflict,            ///< the resource exists or is busy (409)
    payload_too_large,   ///< an upload or a result exceeds a limit (413)
    unsupported_format,  ///< input is not trail data / not a known format (415)
    unprocessable,       ///< well-formed but unusable input, e.g. no valid rows (422)
    cancelled,           ///< a long job was cancelled by its owner
    backend,             ///< an OpenCL backend could not run (callers fall back to the reference)
    internal,            ///< a bug or an I/O failure (500)
    // Refusals of the shared service (server/src/errors/error_table.cpp); compute/ never throws these.
    unauthorized,          ///< no valid token for a route that needs one (401)
    forbidden,             ///< a valid token whose role or ownership does not allow this (403)
    request_timeout,       ///< the request did not arrive, or its work did not end, in time (408)
    too_many_requests,     ///< a rate limit or quota of the caller is reached (429, with Retry-After)
    unavailable,           ///< the server is at capacity for this kind of work (503, with Retry-After)
    insufficient_storage,  ///< the work would exceed the disk budget (507)
  };
  Error(Kind kind, std::string param, const std::string& detail)
      : std::runtime_error(detail), kind_(kind), param_(std::move(param)) {}
  Kind kind() const noexcept { return kind_; }
  const std::string& param() const noexcept { return param_; }

 private:
  Kind kind_;
  std::string param_;
};

/// Short name of a kind, used as the `error` field of an HTTP error body ("invalid_argument", ...).
const char* to_string(Error::Kind kind) noexcept;

inline Error invalid_argument(std::string param, const std::string& detail) {
  return Error(Error::Kind::invalid_argument, std::move(param), detail);
}
inline Error not_found(std::string param, const std::string& detail) {
  return Error(Error::Kind::not_found, std::move(param), detail);
}

}  // namespace trailscope
