// libFuzzer harness: the binary file of a stored gaze dataset (server/src/store/gaze_file.cpp, format in
// proto/gaze_store.md), decode_gaze_file() as GazeStore::get() reads a file back from disk (a damaged or
// foreign file there must be a clean refusal). A file that decodes is a fixed point of the format:
// encoding it gives gaze_file_size() bytes that decode to a dataset encoding to the same bytes.
#include "fuzz_support.hpp"
#include "store/gaze_file.hpp"

using namespace trailscope;
using namespace trailscope::server;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  gaze::GazeDataset ds;
  try {
    ds = decode_gaze_file(fuzz::bytes_of(data, size));
  } catch (const Error& e) {
    fuzz::refuse(e);
    return 0;
  }
  std::string once;
  try {
    once = encode_gaze_file(ds);
  } catch (const Error& e) {
    // What decodes is within the format's limits, so it encodes: any refusal here is a bug.
    std::fprintf(stderr, "decoded but not encodable: %s\n", e.what());
    std::abort();
  }
  if (once.size() != gaze_file_size(ds)) std::abort();
  if (encode_gaze_file(decode_gaze_file(once)) != once) std::abort();
  return 0;
}
