#pragma once
// JSON bodies of the tracker routes (POST /api/v1/videos/synth, /runs/track, /replays): a JSON object
// with known fields only, and the tracker parameters as {name: number}. Every error names its field.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trailscope/tracker/params.hpp"

namespace trailscope::server {

/// The body as a JSON object. Throws invalid_argument("body") for anything else, invalid_argument(name)
/// for a field not in `allowed`.
nlohmann::json parse_body_object(const std::string& body, const std::vector<std::string>& allowed);

/// The tracker parameters of `params` ({name: number}, absent or null = all defaults), checked one by one
/// (tracker::set_param: unknown name, non-number, fractional integer or out of range → invalid_argument
/// naming the parameter) and together (tracker::validate).
tracker::TrackerParams parse_tracker_params(const nlohmann::json& params);

/// A required string field. Throws invalid_argument(name).
std::string string_field(const nlohmann::json& j, const std::string& name);

}  // namespace trailscope::server
