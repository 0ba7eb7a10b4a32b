#pragma once
// The body of the four trail-ingest harnesses (ingest_<format>_fuzz.cpp): the bytes through ingest_bytes(),
// the in-memory twin of ingest_file() (the entry point of the CLI and the upload routes: the same inflater,
// block cutting, readers and assembly; only the bytes' origin differs), with the format forced, so that
// every input reaches that reader; format detection (detect_format) runs on the same bytes first.
#include "fuzz_support.hpp"
#include "trailscope/ingest/ingest.hpp"

namespace trailscope::fuzz {

/// One input of an ingest harness.
inline int ingest_one(const std::uint8_t* data, std::size_t size, ingest::Format format) {
  const auto bytes = bytes_of(data, size);
  try {
    (void)ingest::detect_format(bytes);
  } catch (const Error& e) {
    refuse(e);
  }
  try {
    ingest::IngestOptions opts;
    opts.format = format;
    ingest::IngestReport report;
    const TrailSet trails = ingest::ingest_bytes(bytes, "fuzz input", opts, &report);
    if (report.rows != report.accepted + report.rejected) std::abort();  // the report's own invariant
  } catch (const Error& e) {
    refuse(e);
  }
  return 0;
}

}  // namespace trailscope::fuzz
