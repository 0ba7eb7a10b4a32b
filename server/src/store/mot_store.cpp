#include "store/mot_store.hpp"

#include <algorithm>
#include <fstream>
#include <iostream>
#include <set>

#include "store/column_io.hpp"
#include "store/dataset_ingest.hpp"
#include "store/graph_store.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/metrics/mot_text.hpp"

namespace trailscope::server {
namespace fs = std::filesystem;
using namespace column_io;

namespace {
constexpr char kMagic[] = "TRAILSCOPE-MOT-1";

/// Rows, last frame and distinct ids of parsed records.
template <typename Rows>
nlohmann::json figures(const Rows& rows) {
  std::int64_t last = 0;
  std::set<std::int64_t> ids;
  for (const auto& r : rows) last = std::max(last, r.frame), ids.insert(r.id);
  return {{"rows", rows.size()}, {"frames", last}, {"ids", ids.size()}};
}

}  // namespace

MotStore::MotStore(fs::path root) : root_(std::move(root)) {
  std::error_code ec;
  fs::create_directories(root_ / "mot", ec);
  if (ec) throw io_error(root_ / "mot", "create");
  std::vector<fs::path> orphans;
  for (const auto& e : fs::directory_iterator(root_ / "mot")) {
    const fs::path p = e.path();
    const std::string id = p.stem().string();
    const std::uint64_t n = store_id_number(id, 'm');
    if (p.filename().string().find(".tmp.") != std::string::npos) {
      orphans.push_back(p);
      continue;
    }
    if (p.extension() == ".txt" && n != 0 && !fs::exists(p.parent_path() / (id + ".json"), ec))
      orphans.push_back(p);  // written, but its row never was: an interrupted put
    if (p.extension() != ".json" || n == 0) continue;
    try {
      std::ifstream in(p);
      nlohmann::json m = nlohmann::json::parse(in);
      if (m.value("magic", "") != kMagic || !fs::exists(root_ / "mot" / (id + ".txt"), ec))
        throw io_error(p, "recognise the format of");
      m.erase("magic");
      meta_[id] = std::move(m);
      ids_[n] = id;
      next_ = std::max(next_, n + 1);
    } catch (const std::exception& ex) {
      std::cerr << "store: skipping MOT file '" << id << "': " << ex.what() << "\n";
    }
  }
  for (const auto& p : orphans) fs::remove(p, ec);
}

std::vector<nlohmann::json> MotStore::list() const {
  std::lock_guard lock(mu_);
  std::vector<nlohmann::json> out;
  for (const auto& [n, id] : ids_) out.push_back(meta_.at(id));
  return out;
}

nlohmann::json MotStore::meta(const std::string& id, const std::string& param) const {
  std::lock_guard lock(mu_);
  auto it = meta_.find(id);
  if (it == meta_.end()) throw not_found(param, "MOT file '" + id + "' does not exist");
  return it->second;
}

std::string MotStore::text(const std::string& id, const std::string& param) const {
  std::lock_guard lock(mu_);  // held while reading: a delete cannot remove the file mid-read
  if (!meta_.count(id)) throw not_found(param, "MOT file '" + id + "' does not exist");
  return metrics::read_text_file(root_ / "mot" / (id + ".txt"), param);
}

nlohmann::json MotStore::put(const std::string& name, const std::string& kind, const std::string& text) {
  nlohmann::json row;
  if (kind == "gt")
    row = figures(metrics::parse_mot_gt(text, "body"));
  else if (kind == "result")
    row = figures(metrics::parse_mot_run(text, "body"));
  else if (kind == "points")
    row = figures(metrics::parse_points(text, "body"));
  else
    throw invalid_argument("kind", "kind must be gt, result or points, got '" + kind + "'");
  std::uint64_t n = 0;
  {
    std::lock_guard lock(mu_);
    if (ids_.size() >= limits::kMaxStoredRuns)
      throw Error(Error::Kind::conflict, "mot",
                  "the server stores at most " + std::to_string(limits::kMaxStoredRuns) +
                      " MOT files (kMaxStoredRuns); delete one first");
    n = next_++;
  }
  const std::string id = store_id('m', n);
  const fs::path dir = root_ / "mot", text_file = dir / (id + ".txt");
  row["id"] = id;
  row["name"] = name;
  row["kind"] = kind;
  row["created"] = utc_now_iso();
  row["bytes"] = text.size();
  std::error_code ec;
  try {
    write_file_atomic(text_file, text);
    nlohmann::json on_disk = row;
    on_disk["magic"] = kMagic;
    write_file_atomic(dir / (id + ".json"), json_text(on_disk));  // the row last
    fsync_path(dir);
  } catch (...) {
    fs::remove(text_file, ec);
    throw;
  }
  std::lock_guard lock(mu_);
  ids_[n] = id;
  meta_[id] = row;
  return row;
}

void MotStore::remove(const std::string& id) {
  std::lock_guard lock(mu_);
  if (!meta_.count(id)) throw not_found("mot", "MOT file '" + id + "' does not exist");
  std::error_code ec;
  // The row first: without it the text is an orphan, removed now or at the next start.
  fs::remove(root_ / "mot" / (id + ".json"), ec);
  if (ec) throw io_error(root_ / "mot" / (id + ".json"), "remove");
  fs::remove(root_ / "mot" / (id + ".txt"), ec);
  ids_.erase(store_id_number(id, 'm'));
  meta_.erase(id);
}

}  // namespace trailscope::server
