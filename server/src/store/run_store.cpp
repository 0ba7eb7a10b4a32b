#include "store/run_store.hpp"

#include <algorithm>
#include <cmath>

#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"
#include "trailscope/tracker/run_counts.hpp"

namespace trailscope::server {
namespace fs = std::filesystem;

namespace {
/// Logs kept decoded after use (a long run's log is tens of MB in memory).
constexpr std::size_t kLoadedRuns = 4;
constexpr char kMagic[] = "TRAILSCOPE-RUN-1";
}  // namespace

nlohmann::json run_summary(const tracker::TrackerLog& log) {
  const auto& frames = log.frames;
  const tracker::StateCounts c = tracker::count_states(frames);
  const double total_us = c.tracker_us;
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
          {"track_share", frames.empty() ? 0.0 : static_cast<double>(c.track) / n},
          {"lost_episodes", c.lost_episodes},
          {"has_truth", has_truth},
          {"accuracy", accuracy}};
}

RunStore::RunStore(fs::path root)
    : rows_(std::move(root), {"runs", 'r', ".tslog", kMagic, "run", "runs", "run"}) {}

std::vector<nlohmann::json> RunStore::list() const {
  return rows_.list();
}

nlohmann::json RunStore::meta(const std::string& id) const {
  return rows_.meta(id, "run");
}

fs::path RunStore::log_path(const std::string& id) const {
  return rows_.payload_path(id);
}

void RunStore::touch(const std::string& id, std::shared_ptr<const tracker::TrackerLog> log) const {
  std::lock_guard lock(cache_mu_);
  loaded_.remove_if([&](const auto& e) { return e.first == id; });
  loaded_.emplace_front(id, std::move(log));
  while (loaded_.size() > kLoadedRuns) loaded_.pop_back();
}

std::shared_ptr<const tracker::TrackerLog> RunStore::get(const std::string& id) const {
  rows_.payload_path(id);  // not_found first: the cache may still hold a log deleted a moment ago
  {
    std::lock_guard lock(cache_mu_);
    for (const auto& [lid, log] : loaded_)
      if (lid == id) {
        auto found = log;
        loaded_.remove_if([&](const auto& e) { return e.first == id; });
        loaded_.emplace_front(id, found);
        return found;
      }
  }
  auto log = rows_.read_payload(id, "run", [](const fs::path& p) {
    return std::make_shared<const tracker::TrackerLog>(tracker::read_log(p));
  });
  touch(id, log);
  return log;
}

void RunStore::check_room(std::size_t runs) const {
  rows_.check_room(runs);
}

nlohmann::json RunStore::put(tracker::TrackerLog log, const std::string& origin, const std::string& sweep,
                             const std::string& owner) {
  nlohmann::json names = nlohmann::json::array(), values = nlohmann::json::array();
  for (const auto& p : log.header.params) names.push_back(p.name), values.push_back(p.value);
  nlohmann::json row = {{"run_id", log.header.run_id},
                        {"video", log.header.video_id},
                        {"origin", origin},
                        {"sweep", sweep.empty() ? nlohmann::json(nullptr) : nlohmann::json(sweep)},
                        {"run_created", log.header.created_utc},
                        {"tracker_version", log.header.tracker_version},
                        {"param_names", std::move(names)},
                        {"params", std::move(values)},
                        {"summary", run_summary(log)},
                        {"owner", owner}};
  row = rows_.put(std::move(row), [&](const fs::path& p) { tracker::write_log(log, p, true); });
  touch(row.at("id").get<std::string>(), std::make_shared<const tracker::TrackerLog>(std::move(log)));
  return row;
}

void RunStore::remove(const std::string& id) {
  rows_.remove(id);
  std::lock_guard lock(cache_mu_);
  loaded_.remove_if([&](const auto& e) { return e.first == id; });
}

std::size_t RunStore::size() const {
  return rows_.size();
}

}  // namespace trailscope::server
