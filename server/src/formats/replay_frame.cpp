#include "formats/replay_frame.hpp"

#include <cstdint>

#include <nlohmann/json.hpp>

#include "trailscope/core/json_text.hpp"
#include "trailscope/tof/depth_render.hpp"

namespace trailscope::server {

namespace {
void put_u32le(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xffu));
}
}  // namespace

std::string encode_replay_frame(std::size_t index, const tracker::FrameLog& frame,
                                const std::optional<tof::FrameTruth>& truth, const std::string& depth_png,
                                const std::string& amplitude_png) {
  const nlohmann::json j = {{"type", "frame"},
                            {"index", index},
                            {"timestamp_s", frame.timestamp_s},
                            {"frame", tracker::frame_to_json(frame)},
                            {"truth", truth ? tof::truth_to_json(*truth) : nlohmann::json(nullptr)},
                            {"depth_png", {0, depth_png.size()}},
                            {"amplitude_png", {depth_png.size(), amplitude_png.size()}}};
  const std::string text = json_text(j);
  std::string out;
  out.reserve(8 + text.size() + depth_png.size() + amplitude_png.size());
  out += "TSRF";
  put_u32le(out, static_cast<std::uint32_t>(text.size()));
  out += text;
  out += depth_png;
  out += amplitude_png;
  return out;
}

}  // namespace trailscope::server
