#pragma once
// The one parser of JSON request bodies (POST routes: videos/synth, runs/track, replays, projections,
// compare, metrics, sweeps, bundles): a JSON object with known fields only, typed optional fields, and the
// tracker parameters as {name: number}. Every error is invalid_argument naming its field.
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include <nlohmann/json.hpp>

#include "trailscope/core/error.hpp"
#include "trailscope/tracker/params.hpp"

namespace trailscope::server {

/// `body` as a JSON object. Throws invalid_argument("body", `message`) for anything else.
nlohmann::json parse_json_object(const std::string& body, const std::string& message);

/// Throws invalid_argument(name, "unknown field '<name>'" + (where empty ? "" : " in " + where)) for
/// the first field of `obj` not in `allowed`.
void reject_unknown_fields(const nlohmann::json& obj, const std::vector<std::string>& allowed,
                           const std::string& where = "");

/// The body as a JSON object with fields of `allowed` only: invalid_argument("body", "body: must be a
/// JSON object") or invalid_argument(name) for an unknown field.
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

/// Optional non-negative integer field stored into `out` (left as is when absent). Throws
/// invalid_argument(name) for a negative or non-integer value, or one beyond T's range ("too large").
template <typename T>
void unsigned_field(const nlohmann::json& j, const std::string& name, T& out) {
  auto it = j.find(name);
  if (it == j.end()) return;
  if (!it->is_number_integer() || it->template get<std::int64_t>() < 0)
    throw invalid_argument(name, name + ": must be a non-negative integer");
  const auto v = it->template get<std::uint64_t>();
  if (v > static_cast<std::uint64_t>(std::numeric_limits<T>::max()))
    throw invalid_argument(name, name + ": " + std::to_string(v) + " is too large");
  out = static_cast<T>(v);
}

/// A JSON scalar as the text a parameter parser reads ("32", "0.5", "true", "hourglass"): a whole float
/// prints without its ".0". Throws invalid_argument(name) for an array, object or null.
std::string scalar_text(const nlohmann::json& v, const std::string& name);

}  // namespace trailscope::server
