// Running a tracker over a depth video into a TrackerLog (TrackerRun, tracker_log.hpp), the mapping
// between TrackerParams and a log header's named parameter vector, and a run's state counts
// (run_counts.hpp).
#include <chrono>
#include <cstdio>
#include <ctime>
#include <optional>
#include <random>
#include <string>

#include "trailscope/core/error.hpp"
#include "trailscope/tof/depth_video_io.hpp"
#include "trailscope/tracker/run_counts.hpp"
#include "trailscope/tracker/tracker_log.hpp"

namespace trailscope::tracker {
namespace fs = std::filesystem;

namespace {

/// "run-YYYYMMDD-HHMMSS-xxxx" (UTC, 4 random hex digits so that runs started in the same second differ)
/// and the matching ISO 8601 time.
std::pair<std::string, std::string> new_run_id() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm utc{};
  gmtime_r(&now, &utc);
  char stamp[32], iso[32], id[48];
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &utc);
  std::strftime(iso, sizeof iso, "%Y-%m-%dT%H:%M:%SZ", &utc);
  std::random_device rd;
  std::snprintf(id, sizeof id, "run-%s-%04x", stamp, static_cast<unsigned>(rd()) & 0xffffu);
  return {id, iso};
}

/// The video's name: the file or folder name without extension ("clip" for clip.tsdv or clip/).
std::string video_name(const fs::path& video) {
  fs::path p = video.lexically_normal();
  if (p.filename().empty()) p = p.parent_path();
  return p.stem().string();
}

/// Throws Error(invalid_argument, "first_frame" / "frame_count") for a range outside the video.
void check_range(const tof::VideoInfo& info, const RunOptions& options) {
  if (options.first_frame >= info.frame_count)
    throw invalid_argument("first_frame", "first_frame: " + std::to_string(options.first_frame) +
                                              " is not a frame of the video (it has " +
                                              std::to_string(info.frame_count) + ")");
  const std::size_t available = info.frame_count - options.first_frame;
  const std::size_t count = options.frame_count == 0 ? available : options.frame_count;
  if (count > available)
    throw invalid_argument("frame_count", "frame_count: " + std::to_string(count) + " frames from frame " +
                                              std::to_string(options.first_frame) + " run past the video's " +
                                              std::to_string(info.frame_count));
}

}  // namespace

StateCounts count_states(const std::vector<FrameLog>& frames) {
  StateCounts c;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const State state = frames[i].state;
    (state == State::search ? c.search : state == State::track ? c.track : c.lost) += 1;
    c.lost_episodes += state == State::lost && (i == 0 || frames[i - 1].state != State::lost);
    c.tracker_us += frames[i].times.total_us();
  }
  return c;
}

TrackerParams params_of(const RunHeader& header) {
  TrackerParams p;
  for (const NamedValue& nv : header.params) {
    bool known = false;
    for (const ParamInfo& info : parameter_infos()) known = known || info.name == nv.name;
    // Logs of other tracker versions may carry parameters this one does not have; they are ignored so
    // that such logs can still be re-run and compared.
    if (known) set_param(p, nv.name, nv.value);
  }
  validate(p);
  return p;
}

struct TrackerRun::Impl {
  tof::DepthVideoReader reader;
  std::optional<Tracker> tracker;  ///< built once the range is checked
  RunHeader header;
  std::size_t first = 0, count = 0;

  explicit Impl(const fs::path& video) : reader(video) {}
};

TrackerRun::TrackerRun(const fs::path& video, const TrackerParams& params, const RunOptions& options) {
  impl_ = std::make_unique<Impl>(video);
  const tof::VideoInfo& info = impl_->reader.info();
  check_range(info, options);
  impl_->tracker.emplace(params, info.intrinsics);
  impl_->first = options.first_frame;
  impl_->count = options.frame_count == 0 ? info.frame_count - options.first_frame : options.frame_count;
  RunHeader& h = impl_->header;
  auto [id, created] = new_run_id();
  h.run_id = options.run_id.empty() ? id : options.run_id;
  h.created_utc = created;
  h.video_id = options.video_id.empty() ? video_name(video) : options.video_id;
  const std::vector<double> values = to_vector(impl_->tracker->params());
  for (std::size_t i = 0; i < values.size(); ++i) h.params.push_back({parameter_infos()[i].name, values[i]});
  h.template_bank = impl_->tracker->templates();
  h.intrinsics = info.intrinsics;
  h.fps = info.fps;
  h.video_source = info.source;
  h.frame_count = impl_->count;
}

TrackerRun::~TrackerRun() = default;

const RunHeader& TrackerRun::header() const {
  return impl_->header;
}

TrackerLog TrackerRun::run(const ProgressFn& progress, const FrameFn& on_frame) {
  const tof::VideoInfo& info = impl_->reader.info();
  const std::size_t count = impl_->count;
  TrackerLog log;
  log.header = impl_->header;
  log.frames.reserve(count);
  if (info.has_truth) log.truth.reserve(count);
  const std::size_t step = std::max<std::size_t>(1, count / 100);
  if (progress) progress(0.0, "track");
  for (std::size_t i = 0; i < count; ++i) {
    tof::DepthFrame frame = impl_->reader.read_frame(impl_->first + i);
    FrameLog f = impl_->tracker->process(frame);
    // The log records video frame numbers, so a run that starts at --first N still lines up with the
    // video (replay overlays, truth).
    f.index = impl_->first + i;
    f.timestamp_s = frame.timestamp_s;
    log.frames.push_back(std::move(f));
    const bool go_on = !on_frame || on_frame(log.frames.back(), frame.truth);
    if (info.has_truth) log.truth.push_back(std::move(frame.truth));
    if (progress && ((i + 1) % step == 0 || i + 1 == count))
      progress(static_cast<double>(i + 1) / static_cast<double>(count), "track");
    if (!go_on) break;
  }
  log.header.frame_count = log.frames.size();
  return log;
}

TrackerLog run_tracker(const fs::path& video, const TrackerParams& params, const RunOptions& options,
                       const ProgressFn& progress) {
  return TrackerRun(video, params, options).run(progress);
}

}  // namespace trailscope::tracker
