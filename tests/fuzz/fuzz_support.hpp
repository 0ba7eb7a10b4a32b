#pragma once
// Shared pieces of the libFuzzer harnesses (README "Fuzzing and sanitizers"). Each harness hands the
// fuzzer's bytes to one real parser entry point. A trailscope::Error is the parser's clean refusal of bad
// input (the server turns it into a 4xx) and is caught; anything else escapes, and libFuzzer reports it as a
// crash, as it does every sanitizer report. Error(Kind::internal) is the one exception that is not a
// refusal: it means "a bug or an I/O failure" (HTTP 500), and no byte string may cause it, so
// refuse() aborts on it.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include <unistd.h>

#include "trailscope/core/error.hpp"

namespace trailscope::fuzz {

inline std::string_view bytes_of(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

/// Called in a harness's catch (const Error&): a clean refusal returns, an internal error aborts.
inline void refuse(const Error& e) {
  if (e.kind() == Error::Kind::internal) {
    std::fprintf(stderr, "trailscope::Error(internal, %s): %s\n", e.param().c_str(), e.what());
    std::abort();
  }
}

/// A file holding one input, for a parser whose entry point reads a path (DepthVideoReader).
/// One per process, rewritten for every input, in /dev/shm when it exists (no disk writes at thousands of
/// inputs per second). `suffix` matters only where the parser looks at the extension.
class InputFile {
 public:
  explicit InputFile(const std::string& suffix) {
    const std::filesystem::path dir =
        std::filesystem::is_directory("/dev/shm") ? "/dev/shm" : std::filesystem::temp_directory_path();
    path_ = dir / ("trailscope-fuzz-" + std::to_string(::getpid()) + suffix);
  }
  ~InputFile() {
    std::error_code ec;
    std::filesystem::remove(path_, ec);
  }
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;

  const std::filesystem::path& write(std::string_view bytes) {
    std::ofstream out(path_, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) {
      std::fprintf(stderr, "cannot write %s\n", path_.c_str());
      std::abort();
    }
    return path_;
  }

 private:
  std::filesystem::path path_;
};

}  // namespace trailscope::fuzz
