#include "store/run_store.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>

#include "store/column_io.hpp"
#include "store/dataset_ingest.hpp"
#include "store/graph_store.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"

namespace trailscope::server {
namespace fs = std::filesystem;
using namespace column_io;

namespace {
/// Logs kept decoded after use (a long run's log is tens of MB in memory).
constexpr std::size_t kLoadedRuns = 4;
constexpr char kMagic[] = "TRAILSCOPE-RUN-1";

nlohmann::json number_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

Error too_many() {
  return Error(Error::Kind::conflict, "run",
               "the server stores at most " + std::to_string(limits::kMaxStoredRuns) +
                   " runs (kMaxStoredRuns); delete one first");
}
}  // namespace

nlohmann::json run_summary(const tracker::TrackerLog& log) {
  const auto& frames = log.frames;
  std::size_t track = 0, lost_episodes = 0;
  double total_us = 0;
  bool prev_lost = false;
  for (const auto& f : frames) {
    track += f.state == tracker::State::track;
    const bool lost = f.state == tracker::State::lost;
    lost_episodes += lost && !prev_lost;
    prev_lost = lost;
    total_us += f.times.total_us();
  }
  const double n = static_cast<double>(frames.size());
  const bool has_truth = !log.truth.empty() && std::any_of(log.truth.begin(), log.truth.end(),
                                                           [](const auto& t) { return t.has_value(); });
  nlohmann::json accuracy = nullptr;
  if (has_truth) {
    const tracker::Accuracy a = tracker::evaluate_accuracy(log);
    accuracy = {{"median_error_mm", number_or_null(a.median_error_mm)},
                {"mean_error_mm", number_or_null(a.mean_error_mm)},
                {"p95_error_mm", number_or_null(a.p95_error_mm)},
                {"frames_all_within", number_or_null(a.frames_all_within)},
                {"within_mm", a.within_mm},
                {"visible_pairs", a.visible_pairs},
                {"reported_pairs", a.reported_pairs}};
  }
  const double duration = frames.size() > 1 ? frames.back().timestamp_s - frames.front().timestamp_s : 0.0;
  return {{"frames", frames.size()},
          {"fps", log.header.fps},
          {"duration_s", duration},
          {"tracker_fps", total_us > 0 ? nlohmann::json(n / (total_us * 1e-6)) : nlohmann::json(nullptr)},
          {"track_share", frames.empty() ? 0.0 : static_cast<double>(track) / n},
          {"lost_episodes", lost_episodes},
          {"has_truth", has_truth},
          {"accuracy", accuracy}};
}

RunStore::RunStore(fs::path root) : root_(std::move(root)) {
  std::error_code ec;
  fs::create_directories(root_ / "runs", ec);
  if (ec) throw io_error(root_ / "runs", "create");
  std::vector<fs::path> orphans;
  for (const auto& e : fs::directory_iterator(root_ / "runs")) {
    const fs::path p = e.path();
    const std::string id = p.stem().string();
    const std::uint64_t n = store_id_number(id, 'r');
    if (p.extension() == ".tslog" && n != 0 && !fs::exists(p.parent_path() / (id + ".json"), ec))
      orphans.push_back(p);  // written, but its row never was: an interrupted put
    if (p.extension() == ".tmp" || p.filename().string().find(".tmp.") != std::string::npos)
      orphans.push_back(p);
    if (p.extension() != ".json" || n == 0) continue;
    try {
      std::ifstream in(p);
      nlohmann::json m = nlohmann::json::parse(in);
      if (m.value("magic", "") != kMagic || !fs::exists(root_ / "runs" / (id + ".tslog"), ec))
        throw io_error(p, "recognise the format of");
      m.erase("magic");
      meta_[id] = std::move(m);
      ids_[n] = id;
      next_ = std::max(next_, n + 1);
    } catch (const std::exception& ex) {
      std::cerr << "store: skipping run '" << id << "': " << ex.what() << "\n";
    }
  }
  for (const auto& p : orphans) fs::remove(p, ec);
}

std::vector<nlohmann::json> RunStore::list() const {
  std::lock_guard lock(mu_);
  std::vector<nlohmann::json> out;
  for (const auto& [n, id] : ids_) out.push_back(meta_.at(id));
  return out;
}

nlohmann::json RunStore::meta(const std::string& id) const {
  std::lock_guard lock(mu_);
  auto it = meta_.find(id);
  if (it == meta_.end()) throw not_found("run", "run '" + id + "' does not exist");
  return it->second;
}

fs::path RunStore::log_path(const std::string& id) const {
  std::lock_guard lock(mu_);
  if (!meta_.count(id)) throw not_found("run", "run '" + id + "' does not exist");
  return root_ / "runs" / (id + ".tslog");
}

void RunStore::touch_locked(const std::string& id, std::shared_ptr<const tracker::TrackerLog> log) const {
  loaded_.remove_if([&](const auto& e) { return e.first == id; });
  loaded_.emplace_front(id, std::move(log));
  while (loaded_.size() > kLoadedRuns) loaded_.pop_back();
}

std::shared_ptr<const tracker::TrackerLog> RunStore::get(const std::string& id) const {
  std::lock_guard lock(mu_);
  if (!meta_.count(id)) throw not_found("run", "run '" + id + "' does not exist");
  for (const auto& [lid, log] : loaded_)
    if (lid == id) {
      auto found = log;
      touch_locked(id, found);
      return found;
    }
  // Read under the lock: a delete cannot remove the file mid-read.
  auto log = std::make_shared<const tracker::TrackerLog>(tracker::read_log(root_ / "runs" / (id + ".tslog")));
  touch_locked(id, log);
  return log;
}

void RunStore::check_room(std::size_t runs) const {
  std::lock_guard lock(mu_);
  if (ids_.size() + runs > limits::kMaxStoredRuns) throw too_many();
}

nlohmann::json RunStore::put(tracker::TrackerLog log, const std::string& origin, const std::string& sweep) {
  std::uint64_t n = 0;
  {
    std::lock_guard lock(mu_);
    if (ids_.size() >= limits::kMaxStoredRuns) throw too_many();
    n = next_++;
  }
  const std::string id = store_id('r', n);
  const fs::path dir = root_ / "runs", log_file = dir / (id + ".tslog"), row_file = dir / (id + ".json");
  nlohmann::json names = nlohmann::json::array(), values = nlohmann::json::array();
  for (const auto& p : log.header.params) names.push_back(p.name), values.push_back(p.value);
  nlohmann::json row = {{"id", id},
                        {"run_id", log.header.run_id},
                        {"video", log.header.video_id},
                        {"origin", origin},
                        {"sweep", sweep.empty() ? nlohmann::json(nullptr) : nlohmann::json(sweep)},
                        {"created", utc_now_iso()},
                        {"run_created", log.header.created_utc},
                        {"tracker_version", log.header.tracker_version},
                        {"param_names", std::move(names)},
                        {"params", std::move(values)},
                        {"summary", run_summary(log)}};
  std::error_code ec;
  try {
    tracker::write_log(log, log_file, true);
    row["bytes"] = fs::file_size(log_file, ec);
    nlohmann::json on_disk = row;
    on_disk["magic"] = kMagic;
    write_file_atomic(row_file,
                      json_text(on_disk));  // the row last: a log without one is removed at the next start
    fsync_path(dir);
  } catch (...) {
    fs::remove(log_file, ec);
    throw;
  }
  std::lock_guard lock(mu_);
  ids_[n] = id;
  meta_[id] = row;
  touch_locked(id, std::make_shared<const tracker::TrackerLog>(std::move(log)));
  return row;
}

void RunStore::remove(const std::string& id) {
  std::lock_guard lock(mu_);
  if (!meta_.count(id)) throw not_found("run", "run '" + id + "' does not exist");
  std::error_code ec;
  // The row first: without it the log is an orphan, removed now or at the next start.
  fs::remove(root_ / "runs" / (id + ".json"), ec);
  if (ec) throw io_error(root_ / "runs" / (id + ".json"), "remove");
  fs::remove(root_ / "runs" / (id + ".tslog"), ec);
  ids_.erase(store_id_number(id, 'r'));
  meta_.erase(id);
  loaded_.remove_if([&](const auto& e) { return e.first == id; });
}

std::size_t RunStore::size() const {
  std::lock_guard lock(mu_);
  return ids_.size();
}

}  // namespace trailscope::server
