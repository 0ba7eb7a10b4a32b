#pragma once
// The bytes of an upload route's body: the streamed body file (removed when done) or the in-memory body.
#include <cstdint>
#include <filesystem>
#include <string>

#include "routes/http_types.hpp"

namespace trailscope::server {

/// The whole file. Throws Error(internal) when it cannot be read.
std::string read_whole_file(const std::filesystem::path& p);

/// The upload's bytes, at most `limit` (else Error(payload_too_large, "body", too_large)); an empty
/// upload is invalid_argument("body"). A streamed body file is removed.
std::string upload_bytes(const Request& req, std::uint64_t limit, const std::string& too_large);

}  // namespace trailscope::server
