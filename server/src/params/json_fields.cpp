#include "params/json_fields.hpp"

#include <algorithm>
#include <cmath>

namespace trailscope::server {

nlohmann::json parse_json_object(const std::string& body, const std::string& message) {
  nlohmann::json j = nlohmann::json::parse(body, nullptr, false);
  if (j.is_discarded() || !j.is_object()) throw invalid_argument("body", message);
  return j;
}

void reject_unknown_fields(const nlohmann::json& obj, const std::vector<std::string>& allowed,
                           const std::string& where) {
  for (const auto& [k, v] : obj.items())
    if (std::find(allowed.begin(), allowed.end(), k) == allowed.end())
      throw invalid_argument(k, "unknown field '" + k + "'" + (where.empty() ? "" : " in " + where));
}

nlohmann::json parse_body_object(const std::string& body, const std::vector<std::string>& allowed) {
  nlohmann::json j = parse_json_object(body, "body: must be a JSON object");
  reject_unknown_fields(j, allowed);
  return j;
}

tracker::TrackerParams parse_tracker_params(const nlohmann::json& params) {
  tracker::TrackerParams p;
  if (params.is_null()) return p;
  if (!params.is_object())
    throw invalid_argument("params", "params: must be an object of parameter names and numbers");
  for (const auto& [name, value] : params.items()) {
    if (!value.is_number()) throw invalid_argument(name, name + ": must be a number");
    tracker::set_param(p, name, value.get<double>());
  }
  tracker::validate(p);
  return p;
}

std::string string_field(const nlohmann::json& j, const std::string& name) {
  auto it = j.find(name);
  if (it == j.end()) throw invalid_argument(name, name + ": required");
  if (!it->is_string() || it->get<std::string>().empty())
    throw invalid_argument(name, name + ": must be a non-empty string");
  return it->get<std::string>();
}

double number_field(const nlohmann::json& j, const std::string& name, double fallback) {
  auto it = j.find(name);
  if (it == j.end()) return fallback;
  if (!it->is_number()) throw invalid_argument(name, name + ": must be a number");
  return it->get<double>();
}

std::int64_t integer_field(const nlohmann::json& j, const std::string& name, std::int64_t fallback) {
  auto it = j.find(name);
  if (it == j.end()) return fallback;
  if (!it->is_number_integer()) throw invalid_argument(name, name + ": must be an integer");
  return it->get<std::int64_t>();
}

bool bool_field(const nlohmann::json& j, const std::string& name, bool fallback) {
  auto it = j.find(name);
  if (it == j.end()) return fallback;
  if (!it->is_boolean()) throw invalid_argument(name, name + ": must be true or false");
  return it->get<bool>();
}

std::string scalar_text(const nlohmann::json& v, const std::string& name) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  if (v.is_number_integer() || v.is_number_unsigned()) return v.dump();
  if (v.is_number_float()) {
    // dump() prints 32.0 for a whole float; the parameter parsers take either, but 32 reads better.
    const double d = v.get<double>();
    if (std::isfinite(d) && d == std::floor(d) && std::fabs(d) < 1e15) return std::to_string(std::int64_t(d));
    return v.dump();
  }
  throw invalid_argument(name, name + ": must be a string, a number or a boolean");
}

}  // namespace trailscope::server
