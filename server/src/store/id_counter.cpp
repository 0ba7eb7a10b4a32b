#include "store/id_counter.hpp"

#include <algorithm>
#include <charconv>
#include <fstream>
#include <sstream>

#include "store/column_io.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::server {
namespace fs = std::filesystem;

IdCounter::IdCounter(fs::path file) : file_(std::move(file)) {
  if (file_.empty()) return;
  std::error_code ec;
  fs::create_directories(file_.parent_path(), ec);
  if (ec) throw column_io::io_error(file_.parent_path(), "create");
  // write_file_atomic's temporaries are "<name>.tmp.<random>": a crash mid-write leaves one behind.
  const std::string tmp_prefix = file_.filename().string() + ".tmp.";
  for (const auto& e : fs::directory_iterator(file_.parent_path(), ec))
    if (e.path().filename().string().rfind(tmp_prefix, 0) == 0) fs::remove(e.path(), ec);
  if (!fs::exists(file_, ec)) return;
  std::ifstream in(file_, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  const auto [end, err] = std::from_chars(s.data(), s.data() + s.size(), mark_);
  if (!in || s.empty() || err != std::errc() || end != s.data() + s.size())
    throw Error(Error::Kind::internal, "",
                "store: cannot read the id counter " + file_.string() + " (it must hold one number)");
}

void IdCounter::observe(std::uint64_t n) {
  std::lock_guard lock(mu_);
  mark_ = std::max(mark_, n);
}

std::uint64_t IdCounter::next() {
  std::lock_guard lock(mu_);
  const std::uint64_t n = mark_ + 1;
  if (!file_.empty()) {
    column_io::write_file_atomic(file_, std::to_string(n) + "\n");
    column_io::fsync_path(file_.parent_path());  // the rename itself is durable before the id leaves
  }
  mark_ = n;
  return n;
}

std::uint64_t IdCounter::mark() const {
  std::lock_guard lock(mu_);
  return mark_;
}

}  // namespace trailscope::server
