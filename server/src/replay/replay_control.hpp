#pragma once
// The client's side of the replay protocol (proto/replay_ws.md) without a socket: one viewer's playback
// cursor and the JSON control messages that move it. ReplayViewer (replay_viewer.hpp) owns one and sends
// the state or the error this returns.
#include <cstddef>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

namespace trailscope::server {

/// Playback speeds a viewer may ask for (multiples of the video's own rate).
inline constexpr double kMinReplaySpeed = 0.1, kMaxReplaySpeed = 16;

/// One viewer's playback state.
struct ReplayPlayback {
  bool playing = false;
  std::size_t cursor = 0;           ///< frame shown, 0 .. total - 1
  double speed = 1;                 ///< kMinReplaySpeed .. kMaxReplaySpeed
  std::optional<std::size_t> want;  ///< frame to send next
  bool anchored = false;            ///< the wall-clock anchor belongs to the cursor's timestamp
};

/// Applies one client message (JSON text) to `p` for a replay of `total` frames (>= 1): {"op": "play"}
/// (at the last frame, play starts over from 0), "pause", {"op": "seek", "frame": 0..total-1},
/// {"op": "step", "delta": integer frames, clamped to the video; pauses}, {"op": "speed", "value":
/// kMinReplaySpeed..kMaxReplaySpeed}. Returns nothing when applied, or the error message to send
/// ({"type": "error", "error": "invalid_argument", "param", "detail"}; `p` unchanged) for a text that is
/// not a JSON object with a string "op", an unknown op or a bad value. Never throws for any text.
std::optional<nlohmann::json> apply_replay_control(const std::string& text, std::size_t total,
                                                   ReplayPlayback& p);

}  // namespace trailscope::server
