#include "bundle_stream/stream_control.hpp"

#include <cmath>
#include <map>

#include <nlohmann/json.hpp>

#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/core/text.hpp"
#include "trailscope/geo/web_mercator.hpp"

namespace trailscope::server {
namespace {

constexpr double kWorld = static_cast<double>(geo::kWorldUnits);

double number(const nlohmann::json& v, const char* name, const std::string& what) {
  if (!v.is_number()) throw invalid_argument(name, std::string(name) + " must be " + what);
  const double d = v.get<double>();
  if (!std::isfinite(d)) throw invalid_argument(name, std::string(name) + " must be " + what);
  return d;
}

std::string text_or_empty(const nlohmann::json& v, const char* name) {
  if (v.is_null()) return {};
  if (!v.is_string())
    throw invalid_argument(name, std::string(name) + " must be a string (or null to clear)");
  return v.get<std::string>();
}

}  // namespace

void apply_control(const std::string& text, StreamControl& c) {
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (!j.is_object())
    throw invalid_argument(
        "message", "a control message must be a JSON object such as {\"t\": 1514800000, \"window_s\": 3600}");
  StreamControl next = c;
  bool view = false;
  for (const auto& [key, v] : j.items()) {
    if (key == "t") {
      next.t = v.is_string() ? parse_time(v.get<std::string>(), "t")
                             : number(v, "t", "a number of Unix seconds or an ISO 8601 time");
    } else if (key == "window_s") {
      const double w = number(v, "window_s", "a number of seconds");
      if (!(w >= 60 && w <= limits::kMaxStreamWindowSeconds))
        throw invalid_argument("window_s",
                               "window_s must be in 60.." +
                                   std::to_string(static_cast<long long>(limits::kMaxStreamWindowSeconds)) +
                                   " seconds (limits::kMaxStreamWindowSeconds), got " + format_double(w));
      next.window_s = w;
    } else if (key == "fade_s") {
      next.fade_s = number(v, "fade_s", "a number of seconds");
    } else if (key == "bbox") {
      next.bbox = text_or_empty(v, "bbox"), view = true;
    } else if (key == "callsign") {
      next.callsign = text_or_empty(v, "callsign"), view = true;
    } else if (key == "icao24") {
      next.icao24 = text_or_empty(v, "icao24"), view = true;
    } else {
      throw invalid_argument(key, "unknown field '" + key +
                                      "'; a control message has t, window_s, fade_s, bbox, "
                                      "callsign and icao24");
    }
  }
  if (j.contains("fade_s")) {
    if (!(next.fade_s >= 0 && next.fade_s <= next.window_s))
      throw invalid_argument("fade_s", "fade_s must be in 0..window_s (" + format_double(next.window_s) +
                                           ") seconds, got " + format_double(next.fade_s));
  } else {
    next.fade_s = std::min(next.fade_s, next.window_s);
  }
  if (view) {
    std::map<std::string, std::string> q;
    if (!next.bbox.empty()) q["bbox"] = next.bbox;
    if (!next.callsign.empty()) q["callsign"] = next.callsign;
    if (!next.icao24.empty()) q["icao24"] = next.icao24;
    next.filters = parse_query(q);
    ++next.view_generation;
  }
  c = std::move(next);
}

bundling::Frame stream_frame(const TrailSet& trails, const StreamControl& c, int size) {
  BBox b;
  if (c.filters.bbox) {
    b = *c.filters.bbox;
  } else {
    b = BBox{trails.lon_min(), trails.lat_min(), trails.lon_max(), trails.lat_max()};
  }
  const double x0 = geo::lon_to_unit_x(b.west) * kWorld;
  double x1 = geo::lon_to_unit_x(b.east) * kWorld;
  if (b.west > b.east || x1 <= x0) x1 += kWorld;  // across 180° (or east = 180, which wraps to 0)
  if (b.west == b.east) x1 = x0 + 1;
  const double y0 = geo::lat_to_unit_y(b.north) * kWorld, y1 = geo::lat_to_unit_y(b.south) * kWorld;
  return bundling::Frame::view(x0, y0, x1, std::max(y1, y0 + 1), size);
}

}  // namespace trailscope::server
