#include "params/gaze_filters.hpp"

#include <limits>
#include <string_view>

#include "limits.hpp"
#include "params/json_fields.hpp"
#include "params/query_params.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::server::params {
namespace {

/// A detector threshold: its query name, the EventParams field it sets, and that field's name in
/// gaze::validate's errors.
struct Threshold {
  const char* query;
  double& (*ref)(gaze::EventParams&);
  const char* field_name;
};

// clang-format off
#define TS_GAZE_THRESHOLD(query, member, name) \
  {query, [](gaze::EventParams& p) -> double& { return p.member; }, name}
const Threshold kThresholds[] = {
    TS_GAZE_THRESHOLD("velocity_threshold", ivt.velocity_threshold_deg_s, "velocity_threshold_deg_s"),
    TS_GAZE_THRESHOLD("min_fixation_ms", ivt.min_fixation_ms, "min_fixation_ms"),
    TS_GAZE_THRESHOLD("dispersion", idt.dispersion_threshold_deg, "dispersion_threshold_deg"),
    TS_GAZE_THRESHOLD("min_duration_ms", idt.min_duration_ms, "min_duration_ms"),
    TS_GAZE_THRESHOLD("initial_peak_threshold", adaptive.initial_peak_threshold_deg_s, "initial_peak_threshold_deg_s"),
    TS_GAZE_THRESHOLD("filter_window_ms", adaptive.filter_window_ms, "filter_window_ms"),
    TS_GAZE_THRESHOLD("min_saccade_ms", adaptive.min_saccade_ms, "min_saccade_ms"),
    TS_GAZE_THRESHOLD("adaptive_min_fixation_ms", adaptive.min_fixation_ms, "min_fixation_ms"),
    TS_GAZE_THRESHOLD("glissade_window_ms", adaptive.glissade_window_ms, "glissade_window_ms"),
    TS_GAZE_THRESHOLD("max_velocity", adaptive.max_velocity_deg_s, "max_velocity_deg_s"),
    TS_GAZE_THRESHOLD("max_acceleration", adaptive.max_acceleration_deg_s2, "max_acceleration_deg_s2"),
};
#undef TS_GAZE_THRESHOLD
// clang-format on

std::string replaced(std::string text, std::string_view from, std::string_view to) {
  if (const auto at = text.find(from); at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}
}  // namespace

const std::vector<std::string>& gaze_filter_keys() {
  static const std::vector<std::string> keys = [] {
    std::vector<std::string> k = {"participant", "stimulus", "recording", "t0_ms", "t1_ms", "method"};
    for (const Threshold& t : kThresholds) k.push_back(t.query);
    return k;
  }();
  return keys;
}

std::vector<std::string> with_gaze_filter_keys(std::vector<std::string> extra) {
  extra.insert(extra.end(), gaze_filter_keys().begin(), gaze_filter_keys().end());
  return extra;
}

GazeFilters parse_gaze_filters(const Request& req) {
  GazeFilters f;
  if (auto it = req.query.find("participant"); it != req.query.end()) f.select.participant = it->second;
  if (auto it = req.query.find("stimulus"); it != req.query.end()) f.select.stimulus = it->second;
  if (req.query.count("recording"))
    f.select.recording =
        static_cast<std::size_t>(integer(req, "recording", 0, 0, std::int64_t(limits::kMaxGazeRecordings)));
  f.select.t0_ms = number(req, "t0_ms", 0);
  f.select.t1_ms = number(req, "t1_ms", std::numeric_limits<double>::infinity());
  if (f.select.t0_ms < 0)
    throw invalid_argument(
        "t0_ms",
        "t0_ms must be at least 0 (ms after each recording's first sample), got " + text(req, "t0_ms", ""));
  if (!(f.select.t1_ms > f.select.t0_ms))
    throw invalid_argument("t1_ms", "t1_ms must be later than t0_ms (the window is [t0_ms, t1_ms))");
  if (auto it = req.query.find("method"); it != req.query.end())
    f.events.method = gaze::parse_method(it->second, "method");
  for (const Threshold& t : kThresholds) {
    if (!req.query.count(t.query)) continue;
    const double v = number(req, t.query, 0);
    t.ref(f.events) = v;
    // Each value alone on the defaults (which pass), so that an error is this parameter's even where two
    // methods share a field name (min_fixation_ms).
    gaze::EventParams one;
    t.ref(one) = v;
    try {
      gaze::validate(one);
    } catch (const Error& e) {
      throw invalid_argument(t.query, replaced(e.what(), t.field_name, t.query));
    }
  }
  return f;
}

GazeFilters parse_gaze_filters(const nlohmann::json& body) {
  Request as_query;
  for (const std::string& k : gaze_filter_keys())
    if (body.contains(k)) as_query.query[k] = scalar_text(body[k], k);
  return parse_gaze_filters(as_query);
}

}  // namespace trailscope::server::params
