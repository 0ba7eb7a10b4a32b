#pragma once
// Helpers shared by the tests: where the shared data lives, scratch folders.
#include <filesystem>
#include <map>
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

/// The row of a CSV file whose first field is `key`, as column name -> number (the first column left out);
/// empty when no row has that key. For reference tables such as TrackEval's `pedestrian_detailed.csv`.
std::map<std::string, double> csv_row(const std::filesystem::path& csv, const std::string& key);

/// Sets an environment variable for the lifetime of the object (restoring or removing it after).
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value);
  ~ScopedEnv();
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  std::string name_, old_;
  bool had_ = false;
};

}  // namespace trailscope::test
