#pragma once
// The body of an upload route: the streamed body file (net/http_server.cpp streams bodies of upload routes
// to disk) or the in-memory body of a small request, as bytes or as a file.
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

/// The upload as a file: the streamed body file as it is, or the in-memory body written to a new file in
/// `dir` (the caller removes it). An empty in-memory body is invalid_argument("body"); Error(internal)
/// when the file cannot be written.
std::filesystem::path upload_file(const Request& req, const std::filesystem::path& dir);

}  // namespace trailscope::server
