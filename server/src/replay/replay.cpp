#include "replay/replay.hpp"

#include <algorithm>

#include "errors/error_table.hpp"
#include "formats/replay_frame.hpp"
#include "store/dataset_ingest.hpp"
#include "store/run_store.hpp"
#include "trailscope/core/error.hpp"
#include "limits.hpp"
#include "trailscope/density/png.hpp"

namespace trailscope::server {
namespace fs = std::filesystem;

Replay::Replay(std::string id, std::string video_id, const fs::path& video,
               const tracker::TrackerParams& params, const std::string& colormap,
               std::shared_ptr<RunStore> runs, std::string owner)
    : id_(std::move(id)),
      video_id_(std::move(video_id)),
      params_(params),
      cmap_(&density::colormap(colormap, "colormap")),
      created_(utc_now_iso()),
      runs_(std::move(runs)),
      owner_(std::move(owner)) {
  reader_ = std::make_unique<tof::DepthVideoReader>(video);
  info_ = reader_->info();
  // The run is prepared here, not on the thread, so bad parameters or intrinsics are this request's 400.
  tracker::RunOptions ro;
  ro.video_id = video_id_;
  run_ = std::make_unique<tracker::TrackerRun>(video, params_, ro);
  header_ = run_->header();
  header_.created_utc = created_;
  range_ = tof::video_depth_range(*reader_);  // one colour range for the whole replay
  frames_.reserve(info_.frame_count);
  worker_ = std::thread([this] {
    try {
      tracker::TrackerLog log =
          run_->run({}, [this](const tracker::FrameLog& f, const std::optional<tof::FrameTruth>& truth) {
            if (stop_) return false;
            std::lock_guard lock(mu_);
            frames_.push_back(f);
            truth_.push_back(truth);
            return true;
          });
      if (stop_) {
        std::lock_guard lock(mu_);
        done_ = true;
        return;
      }
      log.header.created_utc = created_;
      const nlohmann::json row = runs_->put(std::move(log), "replay", "", owner_);
      std::vector<std::weak_ptr<ReplayListener>> ls;
      {
        std::lock_guard lock(mu_);
        run_id_ = row.at("id").get<std::string>();
        done_ = true;
        ls = listeners_;
      }
      for (auto& w : ls)
        if (auto l = w.lock()) l->on_run(run_id_);
    } catch (const std::exception& e) {
      std::lock_guard lock(mu_);
      error_ = error_body(e).body;
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
          {"run", run_id_.empty() ? nlohmann::json(nullptr) : nlohmann::json(run_id_)},
          {"error", error_},
          {"viewers", viewers},
          {"owner", owner_}};
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
  return encode_replay_frame(i, fl, truth,
                             density::encode_png(tof::render_depth(frame.depth_mm, w, h, range_, *cmap_)),
                             density::encode_png(tof::render_amplitude(frame.amplitude, w, h)));
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

}  // namespace trailscope::server
