#pragma once
// manifest.json <-> VideoInfo, per-frame entries and ground truth (schema: proto/depth_video.md). Shared by
// the folder and pack layouts, which differ only in how a frame's images are referenced. Internal.
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "trailscope/tof/depth_video.hpp"

namespace trailscope::tof::detail {

/// The video-level fields (format, version, intrinsics, fps, ...) without "frames".
nlohmann::json header_to_json(const VideoInfo& info);
/// Parses and validates the video-level fields. `where` prefixes messages ("v/manifest.json").
/// Throws Error(unsupported_format, "manifest") for a wrong format name or version or a missing or
/// mistyped field, and validate_info's errors (prefixed) for bad values.
VideoInfo header_from_json(const nlohmann::json& j, const std::string& where);

nlohmann::json truth_to_json(const FrameTruth& truth);
FrameTruth truth_from_json(const nlohmann::json& j, const std::string& where);

/// One entry of "frames": its timestamp, image references (file names or byte ranges, as JSON) and truth.
struct FrameEntry {
  double timestamp_s = 0;
  nlohmann::json depth, amplitude;  ///< amplitude is null when the video has none
  std::optional<FrameTruth> truth;
};
nlohmann::json entry_to_json(const FrameEntry& e);
/// Parses entry `index`; checks the truth is present iff info.has_truth and amplitude iff has_amplitude.
FrameEntry entry_from_json(const nlohmann::json& j, const VideoInfo& info, std::size_t index,
                           const std::string& where);

/// Parses a complete manifest: header, then "frames" (an array of frame_count entries with non-decreasing
/// timestamps; Error(unprocessable, "frames") otherwise). Frame-count limits are checked before the
/// entries are parsed.
struct Manifest {
  VideoInfo info;
  std::vector<FrameEntry> frames;
};
Manifest manifest_from_text(const std::string& text, const std::string& where);

}  // namespace trailscope::tof::detail
