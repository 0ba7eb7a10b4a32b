#include "store/row_store.hpp"

#include <fstream>
#include <iostream>

#include "store/column_io.hpp"
#include "store/dataset_ingest.hpp"
#include "trailscope/core/error.hpp"
#include "limits.hpp"

namespace trailscope::server {
namespace fs = std::filesystem;
using namespace column_io;

namespace {
Error full(const RowStore::Kind& kind) {
  return Error(Error::Kind::conflict, kind.param,
               "the server stores at most " + std::to_string(limits::kMaxStoredRuns) + " " + kind.plural +
                   " (kMaxStoredRuns); delete one first");
}
}  // namespace

RowStore::RowStore(fs::path root, Kind kind)
    : dir_(std::move(root) / kind.dir),
      kind_(std::move(kind)),
      index_(kind_.prefix, kind_.noun, dir_ / kIdCounterFile) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec) throw io_error(dir_, "create");
  std::vector<fs::path> orphans;
  for (const auto& e : fs::directory_iterator(dir_)) {
    const fs::path p = e.path();
    const std::string id = p.stem().string();
    const std::uint64_t n = store_id_number(id, kind_.prefix);
    if (p.extension() == ".tmp" || p.filename().string().find(".tmp.") != std::string::npos) {
      orphans.push_back(p);
      continue;
    }
    if (p.extension() == kind_.ext && n != 0 && !fs::exists(dir_ / (id + ".json"), ec))
      orphans.push_back(p);  // written, but its row never was: an interrupted put
    if (p.extension() != ".json" || n == 0) continue;
    try {
      std::ifstream in(p);
      nlohmann::json m = nlohmann::json::parse(in);
      if (m.value("magic", "") != kind_.magic || !fs::exists(path_of(id), ec))
        throw io_error(p, "recognise the format of");
      m.erase("magic");
      index_.add(id, std::move(m));
    } catch (const std::exception& ex) {
      std::cerr << "store: skipping " << kind_.noun << " '" << id << "': " << ex.what() << "\n";
    }
  }
  for (const auto& p : orphans) fs::remove(p, ec);
}

fs::path RowStore::path_of(const std::string& id) const {
  return dir_ / (id + kind_.ext);
}

void RowStore::check_exists_locked(const std::string& id, const std::string& param) const {
  index_.check(id, param);
}

std::vector<nlohmann::json> RowStore::list() const {
  std::lock_guard lock(mu_);
  return index_.list();
}

nlohmann::json RowStore::meta(const std::string& id, const std::string& param) const {
  std::lock_guard lock(mu_);
  return index_.at(id, param);
}

fs::path RowStore::payload_path(const std::string& id) const {
  std::lock_guard lock(mu_);
  check_exists_locked(id, kind_.param);
  return path_of(id);
}

std::size_t RowStore::size() const {
  std::lock_guard lock(mu_);
  return index_.size();
}

void RowStore::check_room(std::size_t items) const {
  std::lock_guard lock(mu_);
  if (index_.size() + items > limits::kMaxStoredRuns) throw full(kind_);
}

nlohmann::json RowStore::put(nlohmann::json row, const std::function<void(const fs::path&)>& write_payload) {
  std::string id;
  {
    std::lock_guard lock(mu_);
    if (index_.size() >= limits::kMaxStoredRuns) throw full(kind_);
    id = index_.next_id();
  }
  const fs::path payload = path_of(id);
  row["id"] = id;
  row["created"] = utc_now_iso();
  std::error_code ec;
  try {
    write_payload(payload);
    row["bytes"] = fs::file_size(payload);
    failpoint("store.row.before_row");
    nlohmann::json on_disk = row;
    on_disk["magic"] = kind_.magic;
    write_file_atomic(dir_ / (id + ".json"), json_text(on_disk));  // the row last
    fsync_path(dir_);
  } catch (...) {
    fs::remove(payload, ec);
    throw;
  }
  std::lock_guard lock(mu_);
  index_.add(id, row);
  return row;
}

void RowStore::remove(const std::string& id) {
  std::lock_guard lock(mu_);
  check_exists_locked(id, kind_.param);
  std::error_code ec;
  // The row first: without it the payload is an orphan, removed now or at the next start.
  fs::remove(dir_ / (id + ".json"), ec);
  if (ec) throw io_error(dir_ / (id + ".json"), "remove");
  failpoint("store.row.remove.after_row");
  fs::remove(path_of(id), ec);
  index_.erase(id);
}

}  // namespace trailscope::server
