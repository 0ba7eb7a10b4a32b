#include "replay/replay_control.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "errors/error_table.hpp"

namespace trailscope::server {
namespace {

nlohmann::json error_message(const std::string& param, const std::string& detail) {
  nlohmann::json body = error_json("invalid_argument", param, detail);
  body["type"] = "error";
  return body;
}

/// An integer field of an op, or nothing when it is absent, not a number, fractional or beyond ±1e15.
std::optional<std::int64_t> integer_field(const nlohmann::json& j, const char* name) {
  auto it = j.find(name);
  if (it == j.end() || !it->is_number()) return std::nullopt;
  const double v = it->get<double>();
  if (!std::isfinite(v) || v != std::floor(v) || std::abs(v) > 1e15) return std::nullopt;
  return static_cast<std::int64_t>(v);
}

}  // namespace

std::optional<nlohmann::json> apply_replay_control(const std::string& text, std::size_t total,
                                                   ReplayPlayback& p) {
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (!j.is_object() || !j.contains("op") || !j["op"].is_string())
    return error_message("op",
                         "a message must be a JSON object with a string \"op\": play, pause, seek, step "
                         "or speed");
  const std::string op = j["op"];
  if (op == "play") {
    if (p.cursor + 1 >= total) p.cursor = 0, p.want = 0;  // play at the end starts over
    p.playing = true;
    p.anchored = false;
  } else if (op == "pause") {
    p.playing = false;
  } else if (op == "seek") {
    const auto f = integer_field(j, "frame");
    if (!f || *f < 0 || static_cast<std::uint64_t>(*f) >= total)
      return error_message("frame", "seek: frame must be an integer in 0.." + std::to_string(total - 1));
    p.cursor = static_cast<std::size_t>(*f);
    p.want = p.cursor;
    p.anchored = false;
  } else if (op == "step") {
    const auto d = integer_field(j, "delta");
    if (!d) return error_message("delta", "step: delta must be an integer (frames, negative = back)");
    p.playing = false;  // stepping is for looking at single frames
    const std::int64_t to = std::clamp<std::int64_t>(static_cast<std::int64_t>(p.cursor) + *d, 0,
                                                     static_cast<std::int64_t>(total) - 1);
    p.cursor = static_cast<std::size_t>(to);
    p.want = p.cursor;
  } else if (op == "speed") {
    auto it = j.find("value");
    const double v = it != j.end() && it->is_number() ? it->get<double>() : std::nan("");
    if (!(v >= kMinReplaySpeed && v <= kMaxReplaySpeed))
      return error_message("value", "speed: value must be a number in 0.1..16 (times the video's rate)");
    p.speed = v;
    p.anchored = false;
  } else {
    return error_message("op", "unknown op '" + op + "': play, pause, seek, step or speed");
  }
  return std::nullopt;
}

}  // namespace trailscope::server
