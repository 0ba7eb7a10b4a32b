#include "manifest.hpp"

#include <cmath>

#include "trailscope/core/error.hpp"
#include "trailscope/tof/depth_video_io.hpp"

namespace trailscope::tof::detail {
using nlohmann::json;

namespace {
[[noreturn]] void schema_error(const std::string& where, const std::string& what) {
  throw Error(Error::Kind::unsupported_format, "manifest", where + ": " + what);
}

const json& field(const json& obj, const char* key, const std::string& where) {
  if (!obj.is_object()) schema_error(where, "expected a JSON object");
  auto it = obj.find(key);
  if (it == obj.end()) schema_error(where, std::string("missing field \"") + key + "\"");
  return *it;
}
double number(const json& obj, const char* key, const std::string& where) {
  const json& v = field(obj, key, where);
  if (!v.is_number()) schema_error(where, std::string("field \"") + key + "\" must be a number");
  return v.get<double>();
}
std::int64_t integer(const json& obj, const char* key, const std::string& where) {
  const json& v = field(obj, key, where);
  if (!v.is_number_integer()) schema_error(where, std::string("field \"") + key + "\" must be an integer");
  return v.get<std::int64_t>();
}
bool boolean(const json& obj, const char* key, const std::string& where) {
  const json& v = field(obj, key, where);
  if (!v.is_boolean()) schema_error(where, std::string("field \"") + key + "\" must be true or false");
  return v.get<bool>();
}
template <std::size_t N>
std::array<double, N> numbers(const json& v, const char* key, const std::string& where) {
  if (!v.is_array() || v.size() != N)
    schema_error(where,
                 std::string("field \"") + key + "\" must be an array of " + std::to_string(N) + " numbers");
  std::array<double, N> out{};
  for (std::size_t i = 0; i < N; ++i) {
    if (!v[i].is_number())
      schema_error(
          where, std::string("field \"") + key + "\" must be an array of " + std::to_string(N) + " numbers");
    out[i] = v[i].get<double>();
  }
  return out;
}
}  // namespace

json header_to_json(const VideoInfo& info) {
  const Intrinsics& k = info.intrinsics;
  json teats = json::array();
  for (auto n : kTeatNames) teats.push_back(std::string(n));
  return {{"format", std::string(kDepthVideoFormat)},
          {"version", kDepthVideoVersion},
          {"intrinsics",
           {{"fx", k.fx},
            {"fy", k.fy},
            {"cx", k.cx},
            {"cy", k.cy},
            {"width", k.width},
            {"height", k.height},
            {"defaulted", k.defaulted}}},
          {"depth_unit", "mm"},
          {"fps", info.fps},
          {"amplitude_scale", info.amplitude_scale},
          {"has_amplitude", info.has_amplitude},
          {"has_truth", info.has_truth},
          {"timestamps_defaulted", info.timestamps_defaulted},
          {"frame_count", info.frame_count},
          {"teats", teats},
          {"source", info.source}};
}

VideoInfo header_from_json(const json& j, const std::string& where) {
  const json& format = field(j, "format", where);
  if (!format.is_string() || format.get<std::string>() != kDepthVideoFormat)
    schema_error(where,
                 "format is " + format.dump() + ", expected \"" + std::string(kDepthVideoFormat) + "\"");
  const std::int64_t version = integer(j, "version", where);
  if (version != kDepthVideoVersion)
    schema_error(where, "version " + std::to_string(version) +
                            " is not supported (this build reads version " +
                            std::to_string(kDepthVideoVersion) + ")");
  VideoInfo info;
  const json& k = field(j, "intrinsics", where);
  const std::string kw = where + " intrinsics";
  info.intrinsics.fx = number(k, "fx", kw);
  info.intrinsics.fy = number(k, "fy", kw);
  info.intrinsics.cx = number(k, "cx", kw);
  info.intrinsics.cy = number(k, "cy", kw);
  const std::int64_t w = integer(k, "width", kw), h = integer(k, "height", kw);
  if (w < 1 || h < 1 || w > 1'000'000 || h > 1'000'000)
    schema_error(kw, "width and height must be in 1..1000000 px");
  info.intrinsics.width = static_cast<int>(w);
  info.intrinsics.height = static_cast<int>(h);
  info.intrinsics.defaulted = boolean(k, "defaulted", kw);
  const json& unit = field(j, "depth_unit", where);
  if (unit != "mm") schema_error(where, "depth_unit must be \"mm\"");
  info.fps = number(j, "fps", where);
  info.amplitude_scale = number(j, "amplitude_scale", where);
  info.has_amplitude = boolean(j, "has_amplitude", where);
  info.has_truth = boolean(j, "has_truth", where);
  info.timestamps_defaulted = boolean(j, "timestamps_defaulted", where);
  const std::int64_t n = integer(j, "frame_count", where);
  if (n < 1)
    throw Error(Error::Kind::unprocessable, "frames",
                where + ": frame_count must be >= 1, not " + std::to_string(n));
  info.frame_count = static_cast<std::size_t>(n);
  info.source = field(j, "source", where);
  try {
    validate_info(info);
  } catch (const Error& e) {
    throw Error(e.kind(), e.param(), where + ": " + e.what());
  }
  return info;
}

json truth_to_json(const FrameTruth& truth) {
  json teats = json::array();
  for (int t = 0; t < kTeatCount; ++t) {
    const TeatTruth& x = truth.teats[t];
    json o = {{"name", std::string(kTeatNames[t])},
              {"tip_mm", x.tip_mm},
              {"tip_px", x.tip_px ? json(*x.tip_px) : json(nullptr)},
              {"visible", x.visible},
              {"visible_fraction", x.visible_fraction},
              {"box_px",
               x.box_px ? json::array({x.box_px->x, x.box_px->y, x.box_px->w, x.box_px->h}) : json(nullptr)},
              {"cup_attached", x.cup_attached}};
    teats.push_back(std::move(o));
  }
  return {{"teats", teats}};
}

FrameTruth truth_from_json(const json& j, const std::string& where) {
  const json& teats = field(j, "teats", where);
  if (!teats.is_array() || teats.size() != kTeatCount)
    schema_error(where, "truth.teats must be an array of " + std::to_string(kTeatCount) + " teats");
  FrameTruth truth;
  for (int t = 0; t < kTeatCount; ++t) {
    const json& o = teats[t];
    const std::string tw = where + " teat " + std::string(kTeatNames[t]);
    const json& name = field(o, "name", tw);
    if (name != std::string(kTeatNames[t]))
      schema_error(
          tw, "name must be \"" + std::string(kTeatNames[t]) + "\" (teats are in the order FL, FR, RL, RR)");
    TeatTruth& x = truth.teats[t];
    x.tip_mm = numbers<3>(field(o, "tip_mm", tw), "tip_mm", tw);
    const json& px = field(o, "tip_px", tw);
    if (!px.is_null()) x.tip_px = numbers<2>(px, "tip_px", tw);
    x.visible = boolean(o, "visible", tw);
    x.visible_fraction = number(o, "visible_fraction", tw);
    const json& box = field(o, "box_px", tw);
    if (!box.is_null()) {
      const auto b = numbers<4>(box, "box_px", tw);
      x.box_px = BoxPx{b[0], b[1], b[2], b[3]};
    }
    x.cup_attached = boolean(o, "cup_attached", tw);
  }
  return truth;
}

json entry_to_json(const FrameEntry& e) {
  json o = {{"timestamp_s", e.timestamp_s}, {"depth", e.depth}};
  if (!e.amplitude.is_null()) o["amplitude"] = e.amplitude;
  if (e.truth) o["truth"] = truth_to_json(*e.truth);
  return o;
}

FrameEntry entry_from_json(const json& j, const VideoInfo& info, std::size_t index,
                           const std::string& where) {
  const std::string fw = where + " frame " + std::to_string(index);
  FrameEntry e;
  e.timestamp_s = number(j, "timestamp_s", fw);
  if (!std::isfinite(e.timestamp_s)) schema_error(fw, "timestamp_s must be finite");
  e.depth = field(j, "depth", fw);
  if (info.has_amplitude)
    e.amplitude = field(j, "amplitude", fw);
  else if (j.contains("amplitude"))
    schema_error(fw, "has an amplitude image but has_amplitude is false");
  if (info.has_truth)
    e.truth = truth_from_json(field(j, "truth", fw), fw);
  else if (j.contains("truth"))
    schema_error(fw, "has ground truth but has_truth is false");
  return e;
}

Manifest manifest_from_text(const std::string& text, const std::string& where) {
  json j;
  try {
    j = json::parse(text);
  } catch (const json::exception& e) {
    // parse_error for bad syntax, out_of_range for a number beyond double's range ("1E400"): both are
    // the file's fault, not ours.
    schema_error(where, std::string("not valid JSON (") + e.what() + ")");
  }
  Manifest m;
  m.info = header_from_json(j, where);
  const json& frames = field(j, "frames", where);
  if (!frames.is_array()) schema_error(where, "field \"frames\" must be an array");
  if (frames.size() != m.info.frame_count)
    throw Error(Error::Kind::unprocessable, "frames",
                where + ": frame_count is " + std::to_string(m.info.frame_count) + " but \"frames\" has " +
                    std::to_string(frames.size()) + " entries");
  m.frames.reserve(frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    m.frames.push_back(entry_from_json(frames[i], m.info, i, where));
    if (i > 0 && m.frames[i].timestamp_s < m.frames[i - 1].timestamp_s)
      throw Error(Error::Kind::unprocessable, "frames",
                  where + ": frame " + std::to_string(i) + " has timestamp_s " +
                      std::to_string(m.frames[i].timestamp_s) + ", earlier than frame " +
                      std::to_string(i - 1) + "'s " + std::to_string(m.frames[i - 1].timestamp_s));
  }
  return m;
}

}  // namespace trailscope::tof::detail
