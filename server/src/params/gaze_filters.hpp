#pragma once
// The query parameters every read route of a stored gaze dataset shares (events, scanpaths, stimulus-space
// tiles, AOIs): which recordings and which window (gaze::GazeFilter, compute/include/trailscope/gaze/
// query.hpp), and the event detector with its thresholds (gaze::EventParams, events.hpp) under the names of
// the `trailscope gaze events` flags:
//   participant, stimulus   exact values of the dataset (an unknown one is 400, checked by
//                           gaze::select_recordings against the dataset)
//   recording               index of one recording, from 0
//   t0_ms, t1_ms            window [t0_ms, t1_ms) in ms after each recording's first sample (default all)
//   method                  ivt | idt | adaptive (default ivt)
//   velocity_threshold      I-VT saccade velocity, deg/s          (IvtParams::velocity_threshold_deg_s)
//   min_fixation_ms         I-VT shortest fixation, ms            (IvtParams::min_fixation_ms)
//   dispersion              I-DT dispersion threshold, deg        (IdtParams::dispersion_threshold_deg)
//   min_duration_ms         I-DT shortest fixation / window, ms   (IdtParams::min_duration_ms)
//   initial_peak_threshold  adaptive initial peak threshold, deg/s
//   (AdaptiveParams::initial_peak_threshold_deg_s) filter_window_ms        adaptive Savitzky-Golay window, ms
//   min_saccade_ms          adaptive shortest saccade, ms
//   adaptive_min_fixation_ms  adaptive shortest fixation, ms
//   glissade_window_ms      adaptive glissade window, ms
//   max_velocity            adaptive noise velocity, deg/s        (AdaptiveParams::max_velocity_deg_s)
//   max_acceleration        adaptive noise acceleration, deg/s^2  (AdaptiveParams::max_acceleration_deg_s2)
// Ranges are the detectors' (gaze::validate); an error names the query parameter, not the field.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "routes/http_types.hpp"
#include "trailscope/gaze/events.hpp"
#include "trailscope/gaze/query.hpp"

namespace trailscope::server::params {

struct GazeFilters {
  gaze::GazeFilter select;   ///< recordings and window
  gaze::EventParams events;  ///< method and thresholds (defaults: events.hpp)
};

/// The parameter names above, for reject_unknown_params.
const std::vector<std::string>& gaze_filter_keys();
/// gaze_filter_keys() plus `extra` (a route's own parameters).
std::vector<std::string> with_gaze_filter_keys(std::vector<std::string> extra);

/// Parses the parameters above (syntax and ranges; values of the dataset are checked when the filter is
/// applied). Throws invalid_argument naming the parameter: "recording: 'x' is not an integer",
/// 'method must be ivt, idt or adaptive, not "x"', "velocity_threshold must be in (0, 5000], not -1", ...
GazeFilters parse_gaze_filters(const Request& req);

/// The same parameters as fields of a POST route's JSON body object (POST …/aoi): each a scalar (string,
/// number or boolean; json_fields.hpp scalar_text) read as the query parameter it stands for, so a field and
/// a parameter are checked alike. Fields other than these are the caller's. Throws what the Request
/// overload throws, and invalid_argument naming the field for an array or object value.
GazeFilters parse_gaze_filters(const nlohmann::json& body);

}  // namespace trailscope::server::params
