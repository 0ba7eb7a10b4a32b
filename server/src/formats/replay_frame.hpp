#pragma once
// The binary frame message of a live replay (proto/replay_ws.md): "TSRF", the JSON header's length
// (u32 little-endian), the JSON header, the depth PNG, the amplitude PNG.
#include <cstddef>
#include <optional>
#include <string>

#include "trailscope/tof/depth_video.hpp"
#include "trailscope/tracker/tracker_log.hpp"

namespace trailscope::server {

/// The message of frame `index`: its JSON header holds type "frame", index, timestamp_s, the frame record
/// (tracker::frame_to_json), truth (or null) and the byte ranges [offset, length] of the two PNGs, which
/// follow the header in that order.
std::string encode_replay_frame(std::size_t index, const tracker::FrameLog& frame,
                                const std::optional<tof::FrameTruth>& truth, const std::string& depth_png,
                                const std::string& amplitude_png);

}  // namespace trailscope::server
