#include "replay/replay_manager.hpp"

#include "limits.hpp"
#include "store/run_store.hpp"
#include "store/video_store.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::server {
namespace fs = std::filesystem;

ReplayManager::ReplayManager(std::shared_ptr<VideoStore> videos, std::shared_ptr<RunStore> runs,
                             fs::path id_file)
    : videos_(std::move(videos)), runs_(std::move(runs)), ids_(std::move(id_file)) {}

ReplayManager::~ReplayManager() {
  std::map<std::uint64_t, std::shared_ptr<Replay>> all;
  {
    std::lock_guard lock(mu_);
    all.swap(replays_);
  }
  for (auto& [n, r] : all) r->stop();
}

std::shared_ptr<Replay> ReplayManager::create(const std::string& video, const tracker::TrackerParams& params,
                                              const std::string& colormap, const std::string& owner) {
  const fs::path pack = videos_->pack_path(video);
  std::lock_guard lock(mu_);
  if (replays_.size() >= limits::kMaxReplays)
    throw Error(Error::Kind::conflict, "replay",
                "at most " + std::to_string(limits::kMaxReplays) +
                    " replays run at once (kMaxReplays); delete one first");
  // A replay that fails to start burns its number: a gap, never a repeat.
  const std::uint64_t n = ids_.next();
  auto r = std::make_shared<Replay>("rp" + std::to_string(n), video, pack, params, colormap, runs_, owner);
  replays_[n] = r;
  return r;
}

std::shared_ptr<Replay> ReplayManager::find(const std::string& id) const {
  std::lock_guard lock(mu_);
  for (const auto& [n, r] : replays_)
    if (r->id() == id) return r;
  return nullptr;
}

std::shared_ptr<Replay> ReplayManager::get(const std::string& id) const {
  auto r = find(id);
  if (!r) throw not_found("replay", "replay '" + id + "' does not exist");
  return r;
}

std::vector<nlohmann::json> ReplayManager::list() const {
  std::lock_guard lock(mu_);
  std::vector<nlohmann::json> out;
  for (const auto& [n, r] : replays_) out.push_back(r->to_json());
  return out;
}

void ReplayManager::remove(const std::string& id) {
  std::shared_ptr<Replay> r;
  {
    std::lock_guard lock(mu_);
    for (auto it = replays_.begin(); it != replays_.end(); ++it)
      if (it->second->id() == id) {
        r = it->second;
        replays_.erase(it);
        break;
      }
  }
  if (!r) throw not_found("replay", "replay '" + id + "' does not exist");
  r->stop();
}

}  // namespace trailscope::server
