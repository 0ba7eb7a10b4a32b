#pragma once
// Ingest a file into the store as one dataset: the same step for `trailscope ingest` and for
// POST /api/v1/datasets. The dataset appears whole or not at all.
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "store/dataset_store.hpp"
#include "trailscope/core/progress.hpp"

namespace trailscope::server {

struct IngestRequest {
  std::filesystem::path file;         ///< plain or gzip
  std::string name;                   ///< dataset id (validated)
  std::optional<std::string> format;  ///< a format name; detected from content when absent
  std::string owner;                  ///< the owner name the dataset records ("" from the CLI)
  /// Split flights between legs and at teleports (ingest::IngestOptions::split_jumps; unset: on).
  std::optional<bool> split_jumps;
  /// Called with the assembled dataset before it is written; a throw (a disk budget's 507) stops the
  /// ingest with nothing written.
  std::function<void(const Dataset&)> before_write;
};

/// Parses `req.file`, assembles flights and stores the dataset. Throws what ingest_file throws
/// (unsupported_format, unprocessable, not_found), conflict("name") when the id exists, cancelled.
std::shared_ptr<const Dataset> ingest_into_store(DatasetStore& store, const IngestRequest& req,
                                                 const ProgressFn& progress, const CancelToken* cancel);

/// Current UTC time as ISO 8601 ("2026-11-22T11:00:00Z").
std::string utc_now_iso();
/// A Unix time (seconds, UTC) as ISO 8601 to the second ("2018-01-01T06:00:00Z").
std::string iso_utc(double unix_seconds);

}  // namespace trailscope::server
