// libFuzzer harness: the gaze file readers (compute/src/gaze/ingest.cpp), all eight formats through
// read_gaze(), the entry point of `trailscope gaze ingest` (read_gaze_file reads the file and calls it).
// The FIRST BYTE picks how the rest is read, so that one corpus covers every reader and the fuzzer can
// move an input from one reader to another:
//   byte % 9      0..7: that GazeFormat forced (the enumerator order of ingest.hpp); 8: detected from the
//                 content (detect_gaze_format, as the CLI does without --format)
//   byte / 9 % 3  the eye of a binocular file: average, left, right
//   byte / 27 % 2 1: a screen of 1920 x 1080 px given (Tobii's normalised coordinates need one)
// The rest is the file's bytes. Besides a clean refusal, what every reader promises is checked: per
// recording equally long sample columns (and annotation columns), an invalid sample is NaN and a valid
// one finite, and at least one sample in all.
#include <cmath>

#include "fuzz_support.hpp"
#include "trailscope/gaze/ingest.hpp"

using namespace trailscope;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const unsigned pick = data[0];
  const auto content = fuzz::bytes_of(data + 1, size - 1);
  try {
    (void)gaze::detect_gaze_format(content);
  } catch (const Error& e) {
    fuzz::refuse(e);
  }
  gaze::GazeIngestOptions opt;
  if (pick % 9 < 8) opt.format = static_cast<gaze::GazeFormat>(pick % 9);
  opt.eye = static_cast<gaze::Eye>(pick / 9 % 3);
  if (pick / 27 % 2) opt.geometry.width_px = 1920, opt.geometry.height_px = 1080;
  try {
    const gaze::GazeDataset ds = gaze::read_gaze(content, opt);
    if (ds.recordings.empty() || ds.total_samples() == 0) std::abort();
    for (const gaze::Recording& r : ds.recordings) {
      const std::size_t n = r.t_ms.size();
      if (r.x.size() != n || r.y.size() != n || r.valid.size() != n) std::abort();
      for (std::size_t k = 0; k < n; ++k) {
        const bool finite = std::isfinite(r.x[k]) && std::isfinite(r.y[k]);
        if (r.valid[k] > 1 || (r.valid[k] == 1) != finite) std::abort();
      }
      for (const auto& [name, labels] : r.annotations)
        if (labels.size() != n) std::abort();
    }
  } catch (const Error& e) {
    fuzz::refuse(e);
  }
  return 0;
}
