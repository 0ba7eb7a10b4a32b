#include "test_support.hpp"

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>
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

std::map<std::string, double> csv_row(const fs::path& csv, const std::string& key) {
  std::ifstream in(csv);
  std::string header, line;
  std::getline(in, header);
  const auto split = [](const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    for (std::string f; std::getline(ss, f, ',');) out.push_back(f);
    return out;
  };
  const auto names = split(header);
  while (std::getline(in, line)) {
    const auto values = split(line);
    if (values.empty() || values[0] != key) continue;
    std::map<std::string, double> row;
    for (std::size_t k = 1; k < names.size() && k < values.size(); ++k) row[names[k]] = std::stod(values[k]);
    return row;
  }
  return {};
}

ScopedEnv::ScopedEnv(const char* name, const char* value) : name_(name) {
  if (const char* old = std::getenv(name)) old_ = old, had_ = true;
  setenv(name, value, 1);
}
ScopedEnv::~ScopedEnv() {
  if (had_)
    setenv(name_.c_str(), old_.c_str(), 1);
  else
    unsetenv(name_.c_str());
}

}  // namespace trailscope::test
