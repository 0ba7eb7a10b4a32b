#pragma once
// Tracker log: a run header and one FrameLog per frame — the format tracker runs are written, uploaded,
// replayed and compared in. Schema: proto/tracker_log.proto (package trailscope.tracker.v1); JSON is that
// schema's canonical protobuf JSON mapping (lowerCamelCase field names). Documented in
// proto/tracker_log.md. Files: binary protobuf (".tslog") or JSON (".json"), written atomically.
#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trailscope/core/progress.hpp"
#include "trailscope/tof/depth_video.hpp"
#include "trailscope/tracker/tracker.hpp"

namespace trailscope::tracker {

/// Schema version written into every log; readers accept versions <= this one.
inline constexpr int kTrackerLogVersion = 1;

/// One named parameter value of the run (the full vector, in parameter_infos() order).
struct NamedValue {
  std::string name;
  double value = 0;
};

struct RunHeader {
  int version = kTrackerLogVersion;
  std::string run_id;    ///< unique id of the run (e.g. "run-20261122-155900-3f2a")
  std::string video_id;  ///< the video's id in the store, or its file name
  std::string tracker_version = std::string(kTrackerVersion);
  std::vector<NamedValue> params;  ///< every parameter, parameter_infos() order
  std::vector<Tracker::TemplateInfo> template_bank;
  tof::Intrinsics intrinsics;
  double fps = 0;
  std::size_t frame_count = 0;                             ///< frames in the log
  std::string created_utc;                                 ///< ISO 8601, e.g. "2026-11-22T15:59:00Z"
  nlohmann::json video_source = nlohmann::json::object();  ///< the video's source (generator, scenario, seed)
};

/// A run: header, frames, and (when the video had ground truth) the truth per frame so that a log alone
/// can be scored and replayed with overlays.
struct TrackerLog {
  RunHeader header;
  std::vector<FrameLog> frames;
  std::vector<std::optional<tof::FrameTruth>> truth;  ///< empty, or one per frame
};

/// The header's parameter vector turned back into TrackerParams (unknown names ignored, missing ones
/// default). Throws Error(invalid_argument, name) for an out-of-range value.
TrackerParams params_of(const RunHeader& header);

// --- files and wire (implemented with protobuf; see proto/tracker_log.proto) ---
enum class LogEncoding { binary, json };
/// Serialises a log. JSON is compact (no whitespace). Throws Error(invalid_argument, "log") for a log
/// decode_log would refuse (header.frame_count != frames.size(), truth neither empty nor one per frame),
/// Error(payload_too_large, "log") when the result would exceed limits::kMaxRunBytes or kMaxRunFrames.
std::string encode_log(const TrackerLog& log, LogEncoding encoding);
/// Parses a log in either encoding (told apart by the first non-blank byte, '{' = JSON). Throws
/// Error(unsupported_format, "log") for bytes that are neither, Error(invalid_argument, "log") naming the
/// field and frame of a structural fault (a teat array not of 4, truth count mismatch, an unknown state,
/// a version newer than kTrackerLogVersion), Error(payload_too_large, "log") beyond limits::kMaxRunBytes
/// or kMaxRunFrames.
TrackerLog decode_log(std::string_view bytes);
/// Writes atomically (temporary file + rename); the encoding follows the extension (".json" = JSON,
/// anything else binary). Throws Error(conflict, "output") when the file exists and !overwrite, as
/// encode_log, and Error(internal, "output") when the file cannot be written.
void write_log(const TrackerLog& log, const std::filesystem::path& path, bool overwrite = false);
/// Throws Error(not_found, "log") for a missing file, otherwise as decode_log (message prefixed by the path).
TrackerLog read_log(const std::filesystem::path& path);

/// JSON of one frame record, the same object the log's JSON mapping holds in "frames" (used by the live
/// replay to stream frames without a whole log).
nlohmann::json frame_to_json(const FrameLog& frame);
nlohmann::json header_to_json(const RunHeader& header);

// --- running ---
struct RunOptions {
  std::string run_id;    ///< empty = generated
  std::string video_id;  ///< empty = the video file's name
  std::size_t first_frame = 0;
  std::size_t frame_count = 0;  ///< 0 = to the end
};
/// Called after each tracked frame with its record and its ground truth (nullopt when the video has none
/// for it); returning false stops the run after that frame.
using FrameFn = std::function<bool(const FrameLog& frame, const std::optional<tof::FrameTruth>& truth)>;

/// One run of a tracker over a depth video, made ready before it starts: the video is open, the frame
/// range checked, the tracker built and the log's header assembled (run id "run-YYYYMMDD-HHMMSS-xxxx",
/// creation time, the full parameter vector, templates, intrinsics, fps, video source; frame_count = the
/// frames of the range). A caller thus sees bad parameters or a bad range before tracking, and can show
/// the header while frames are tracked (the server's live replay).
class TrackerRun {
 public:
  /// Opens `video` (any DepthVideoReader source). Throws Error(invalid_argument, "first_frame" /
  /// "frame_count") for a range outside the video, as DepthVideoReader and Tracker otherwise.
  TrackerRun(const std::filesystem::path& video, const TrackerParams& params, const RunOptions& options = {});
  ~TrackerRun();
  TrackerRun(const TrackerRun&) = delete;
  TrackerRun& operator=(const TrackerRun&) = delete;

  const RunHeader& header() const;
  /// Tracks the range and returns the log with the video's ground truth (header().frame_count becomes the
  /// frames tracked). FrameLog::index is the frame's number in the video (first_frame + i). Progress
  /// ("track") about every 1 % of the frames; `on_frame` after every frame. `on_frame` returning false
  /// ends the run early (the log then holds the frames tracked so far); either may also cancel by
  /// throwing, which propagates. Call once.
  TrackerLog run(const ProgressFn& progress = {}, const FrameFn& on_frame = {});

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// TrackerRun(video, params, options).run(progress): the whole run in one call.
TrackerLog run_tracker(const std::filesystem::path& video, const TrackerParams& params,
                       const RunOptions& options = {}, const ProgressFn& progress = {});

// --- accuracy against ground truth (the figures a tracker run is judged by) ---
struct TeatAccuracy {
  std::size_t visible_frames = 0;  ///< frames where the truth says visible
  std::size_t reported = 0;        ///< of those, frames where the tracker reported the teat visible
  double median_error_mm = 0;      ///< over reported frames (NaN when none)
  double p95_error_mm = 0;
};
struct Accuracy {
  std::array<TeatAccuracy, tof::kTeatCount> teats{};
  std::size_t frames = 0;          ///< frames with truth
  std::size_t visible_pairs = 0;   ///< (frame, teat) pairs with a visible truth
  std::size_t reported_pairs = 0;  ///< of those, reported visible by the tracker
  double median_error_mm = 0;      ///< 3D tip error over reported pairs, mm (NaN when none)
  double mean_error_mm = 0;
  double p95_error_mm = 0;
  /// Share of frames with at least one visible teat in which EVERY visible teat was reported visible
  /// within `within_mm` (frames with no visible teat are not counted).
  double frames_all_within = 0;
  double within_mm = 10;
  double track_share = 0;         ///< share of frames in TRACK
  std::size_t lost_episodes = 0;  ///< maximal runs of LOST frames
  /// Per frame: the largest error over the visible teats (NaN when none visible, +inf when a visible
  /// teat was not reported) — for timelines.
  std::vector<double> frame_max_error_mm;
};
/// Scores a log against its truth. Quantiles interpolate linearly between closest ranks (numpy's
/// default). Throws Error(unprocessable, "truth") when the log has none, Error(invalid_argument, "truth")
/// when it is not one per frame, Error(invalid_argument, "within_mm") unless within_mm is finite and > 0.
Accuracy evaluate_accuracy(const TrackerLog& log, double within_mm = 10.0);
/// snake_case keys as the fields; NaN and infinities as the strings "NaN", "Infinity" (as the log's JSON).
nlohmann::json to_json(const Accuracy& a);

}  // namespace trailscope::tracker
