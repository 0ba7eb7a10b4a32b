#include "replay/replay.hpp"

#include <algorithm>
#include <cstdio>
#include <random>

#include "errors/error_table.hpp"
#include "store/dataset_ingest.hpp"
#include "store/run_store.hpp"
#include "store/video_store.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/density/png.hpp"

namespace trailscope::server {
namespace fs = std::filesystem;

namespace {
/// Frames whose depth fixes a replay's colour range: enough to see the scene, few enough to open fast.

/// "run-20261122-155900-3f2a": the run id format of tracker_log.hpp.
std::string new_run_id() {
  std::string t = utc_now_iso();  // 2026-11-22T15:59:00Z
  std::string compact;
  for (char c : t.substr(0, 19))
    if (c != '-' && c != ':') compact += c == 'T' ? '-' : c;
  std::random_device rd;
  char suffix[8];
  std::snprintf(suffix, sizeof suffix, "%04x", rd() & 0xffffu);
  return "run-" + compact + "-" + suffix;
}

void put_u32le(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xffu));
}
}  // namespace

Replay::Replay(std::string id, std::string video_id, const fs::path& video,
               const tracker::TrackerParams& params, const std::string& colormap,
               std::shared_ptr<RunStore> runs)
    : id_(std::move(id)),
      video_id_(std::move(video_id)),
      params_(params),
      cmap_(&density::colormap(colormap, "colormap")),
      created_(utc_now_iso()),
      runs_(std::move(runs)) {
  reader_ = std::make_unique<tof::DepthVideoReader>(video);
  info_ = reader_->info();
  // The tracker is built here, not on the thread, so bad parameters or intrinsics are this request's 400.
  tracker::Tracker tracker(params_, info_.intrinsics);
  header_.run_id = new_run_id();
  header_.video_id = video_id_;
  for (const auto& p : tracker::parameter_infos())
    header_.params.push_back({p.name, tracker::get_param(params_, p.name)});
  header_.template_bank = tracker.templates();
  header_.intrinsics = info_.intrinsics;
  header_.fps = info_.fps;
  header_.frame_count = info_.frame_count;
  header_.created_utc = created_;
  header_.video_source = info_.source;
  range_ = tof::video_depth_range(*reader_);  // one colour range for the whole replay
  frames_.reserve(info_.frame_count);
  worker_ = std::thread([this, video, t = std::move(tracker)]() mutable {
    try {
      tof::DepthVideoReader reader(video);
      for (std::size_t i = 0; i < info_.frame_count; ++i) {
        if (stop_) break;
        tof::DepthFrame frame = reader.read_frame(i);
        tracker::FrameLog fl = t.process(frame);
        std::lock_guard lock(mu_);
        frames_.push_back(std::move(fl));
        truth_.push_back(std::move(frame.truth));
      }
      if (stop_) {
        std::lock_guard lock(mu_);
        done_ = true;
        return;
      }
      tracker::TrackerLog log;
      {
        std::lock_guard lock(mu_);
        log.header = header_;
        log.frames = frames_;
        if (info_.has_truth) log.truth = truth_;
      }
      log.header.frame_count = log.frames.size();
      const nlohmann::json row = runs_->put(std::move(log), "replay");
      std::vector<std::weak_ptr<ReplayListener>> ls;
      {
        std::lock_guard lock(mu_);
        run_ = row.at("id").get<std::string>();
        done_ = true;
        ls = listeners_;
      }
      for (auto& w : ls)
        if (auto l = w.lock()) l->on_run(run_);
    } catch (const std::exception& e) {
      std::lock_guard lock(mu_);
      error_ = nlohmann::json::parse(error_response(e).body);
      done_ = true;
    }
  });
}

Replay::~Replay() {
  stop_ = true;
  if (worker_.joinable()) worker_.join();
}

nlohmann::json Replay::to_json() const {
  nlohmann::json params = nlohmann::json::object();
  for (const auto& p : header_.params) params[p.name] = p.value;
  std::lock_guard lock(mu_);
  std::size_t viewers = 0;
  for (const auto& w : listeners_) viewers += !w.expired();
  return {{"id", id_},
          {"video", video_id_},
          {"frames", info_.frame_count},
          {"fps", info_.fps},
          {"width", info_.intrinsics.width},
          {"height", info_.intrinsics.height},
          {"has_truth", info_.has_truth},
          {"params", std::move(params)},
          {"colormap", cmap_->name},
          {"depth_range_mm", {range_.min_mm, range_.max_mm}},
          {"created", created_},
          {"ws", "/api/v1/replays/" + id_ + "/ws"},
          {"computed", frames_.size()},
          {"done", done_},
          {"run", run_.empty() ? nlohmann::json(nullptr) : nlohmann::json(run_)},
          {"error", error_},
          {"viewers", viewers}};
}

nlohmann::json Replay::header_json() const {
  return tracker::header_to_json(header_);
}

std::size_t Replay::computed() const {
  std::lock_guard lock(mu_);
  return frames_.size();
}

bool Replay::done() const {
  std::lock_guard lock(mu_);
  return done_;
}

std::optional<double> Replay::timestamp(std::size_t i) const {
  std::lock_guard lock(mu_);
  if (i >= frames_.size()) return std::nullopt;
  return frames_[i].timestamp_s;
}

std::optional<std::string> Replay::frame_message(std::size_t i) const {
  tracker::FrameLog fl;
  std::optional<tof::FrameTruth> truth;
  {
    std::lock_guard lock(mu_);
    if (i >= frames_.size()) return std::nullopt;
    fl = frames_[i];
    truth = truth_[i];
  }
  tof::DepthFrame frame;
  {
    std::lock_guard lock(reader_mu_);
    frame = reader_->read_frame(i);
  }
  const int w = info_.intrinsics.width, h = info_.intrinsics.height;
  const std::string depth = density::encode_png(tof::render_depth(frame.depth_mm, w, h, range_, *cmap_));
  const std::string amplitude = density::encode_png(tof::render_amplitude(frame.amplitude, w, h));
  const nlohmann::json j = {{"type", "frame"},
                            {"index", i},
                            {"timestamp_s", fl.timestamp_s},
                            {"frame", tracker::frame_to_json(fl)},
                            {"truth", truth ? tof::truth_to_json(*truth) : nlohmann::json(nullptr)},
                            {"depth_png", {0, depth.size()}},
                            {"amplitude_png", {depth.size(), amplitude.size()}}};
  const std::string text = json_text(j);
  std::string out;
  out.reserve(8 + text.size() + depth.size() + amplitude.size());
  out += "TSRF";
  put_u32le(out, static_cast<std::uint32_t>(text.size()));
  out += text;
  out += depth;
  out += amplitude;
  return out;
}

void Replay::attach(const std::shared_ptr<ReplayListener>& l) {
  std::lock_guard lock(mu_);
  std::erase_if(listeners_, [](const auto& w) { return w.expired(); });
  if (listeners_.size() >= limits::kMaxReplayViewers)
    throw Error(Error::Kind::conflict, "replay",
                "replay '" + id_ + "' has its limit of " + std::to_string(limits::kMaxReplayViewers) +
                    " viewers (kMaxReplayViewers)");
  listeners_.push_back(l);
}

void Replay::detach(const ReplayListener* l) {
  std::lock_guard lock(mu_);
  std::erase_if(listeners_, [&](const auto& w) {
    auto s = w.lock();
    return !s || s.get() == l;
  });
}

std::size_t Replay::viewers() const {
  std::lock_guard lock(mu_);
  std::size_t n = 0;
  for (const auto& w : listeners_) n += !w.expired();
  return n;
}

bool Replay::has_room() const {
  return viewers() < limits::kMaxReplayViewers;
}

void Replay::stop() {
  stop_ = true;
  if (worker_.joinable() && worker_.get_id() != std::this_thread::get_id()) worker_.join();
  std::vector<std::weak_ptr<ReplayListener>> ls;
  {
    std::lock_guard lock(mu_);
    ls = listeners_;
  }
  for (auto& w : ls)
    if (auto l = w.lock()) l->on_close();
}

ReplayManager::ReplayManager(std::shared_ptr<VideoStore> videos, std::shared_ptr<RunStore> runs)
    : videos_(std::move(videos)), runs_(std::move(runs)) {}

ReplayManager::~ReplayManager() {
  std::map<std::uint64_t, std::shared_ptr<Replay>> all;
  {
    std::lock_guard lock(mu_);
    all.swap(replays_);
  }
  for (auto& [n, r] : all) r->stop();
}

std::shared_ptr<Replay> ReplayManager::create(const std::string& video, const tracker::TrackerParams& params,
                                              const std::string& colormap) {
  const fs::path pack = videos_->pack_path(video);
  std::lock_guard lock(mu_);
  if (replays_.size() >= limits::kMaxReplays)
    throw Error(Error::Kind::conflict, "replay",
                "at most " + std::to_string(limits::kMaxReplays) +
                    " replays run at once (kMaxReplays); delete one first");
  const std::uint64_t n = next_;
  auto r = std::make_shared<Replay>("rp" + std::to_string(n), video, pack, params, colormap, runs_);
  ++next_;
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
