#pragma once
// Helpers shared by the tests: where the shared data lives, scratch folders.
#include <filesystem>
#include <string>

namespace trailscope::test {

/// ../shared (from $TRAILSCOPE_SHARED, set by CTest); tests that need real data read it from there.
std::filesystem::path shared_dir();
/// A path under ../shared/data.
std::filesystem::path shared_data(const std::string& relative);
/// The source tree root (from $TRAILSCOPE_SOURCE).
std::filesystem::path source_dir();
/// A fresh, empty folder removed when the object is destroyed.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace trailscope::test
