// libFuzzer harness: trail ingest, format opensky_csv (compute/src/ingest/opensky_csv*), through
// ingest_file() — the one entry point of the CLI and the upload routes — with the format forced, so that
// every input reaches this reader; format detection (detect_format) runs on the same bytes first.
#include "fuzz_support.hpp"
#include "trailscope/ingest/ingest.hpp"

using namespace trailscope;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static fuzz::InputFile file(".opensky_csv");
  const auto bytes = fuzz::bytes_of(data, size);
  try {
    (void)ingest::detect_format(bytes);
  } catch (const Error& e) {
    fuzz::refuse(e);
  }
  try {
    ingest::IngestOptions opts;
    opts.format = ingest::Format::opensky_csv;
    ingest::IngestReport report;
    const TrailSet trails = ingest::ingest_file(file.write(bytes).string(), opts, &report);
    if (report.rows != report.accepted + report.rejected) std::abort();  // the report's own invariant
  } catch (const Error& e) {
    fuzz::refuse(e);
  }
  return 0;
}
