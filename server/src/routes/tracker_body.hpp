#pragma once
// JSON bodies of the POST routes (videos/synth, runs/track, replays, projections, compare, ...): a JSON
// object with known fields only, typed optional fields, and the tracker parameters as {name: number}.
// Every error names its field.
#include <cstdint>
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

/// Optional typed fields: `fallback` when absent; invalid_argument(name) for a value of another type
/// (integer_field also refuses a fractional number).
double number_field(const nlohmann::json& j, const std::string& name, double fallback);
std::int64_t integer_field(const nlohmann::json& j, const std::string& name, std::int64_t fallback);
bool bool_field(const nlohmann::json& j, const std::string& name, bool fallback);

}  // namespace trailscope::server
