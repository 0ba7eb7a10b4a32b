#pragma once
// The uploaded file an ingest job reads: removed when the job lets go of it.
#include <filesystem>
#include <system_error>

namespace trailscope::server {

/// Removes `path` (if set) when destroyed; errors are ignored (the file may be gone already). Held by the
/// job's work so that the upload goes when the work ends; held by a shared_ptr the job's closure captures,
/// it also goes when a queued job is cancelled unrun and its closure is dropped.
struct UploadFile {
  std::filesystem::path path;
  ~UploadFile() {
    std::error_code ec;
    if (!path.empty()) std::filesystem::remove(path, ec);
  }
};

}  // namespace trailscope::server
