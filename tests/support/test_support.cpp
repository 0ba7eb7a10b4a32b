#include "test_support.hpp"

#include <cstdlib>
#include <random>
#include <stdexcept>

namespace trailscope::test {
namespace fs = std::filesystem;

static fs::path env_path(const char* name, const char* fallback) {
  const char* v = std::getenv(name);
  return fs::path(v && *v ? v : fallback);
}

fs::path shared_dir() {
  return env_path("TRAILSCOPE_SHARED", TRAILSCOPE_SHARED_DEFAULT);
}
fs::path shared_data(const std::string& relative) {
  return shared_dir() / "data" / relative;
}
fs::path source_dir() {
  return env_path("TRAILSCOPE_SOURCE", TRAILSCOPE_SOURCE_DIR);
}

TempDir::TempDir() {
  std::random_device rd;
  for (int attempt = 0; attempt < 16; ++attempt) {
    fs::path p = fs::temp_directory_path() / ("trailscope-test-" + std::to_string(rd()));
    if (fs::create_directory(p)) {
      path_ = p;
      return;
    }
  }
  throw std::runtime_error("cannot create a temporary directory");
}
TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

}  // namespace trailscope::test
