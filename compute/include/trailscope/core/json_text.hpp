#pragma once
// JSON text for the wire and for files. Messages can quote input bytes that are not UTF-8 (a damaged
// upload, a field of binary junk); nlohmann::json::dump() throws on those, so every serialisation goes
// through here and replaces them with U+FFFD instead.
#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

namespace trailscope {

/// `j` as JSON text; `indent` < 0 gives the compact form. Never throws on invalid UTF-8.
inline std::string json_text(const nlohmann::json& j, int indent = -1) {
  return j.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

/// A figure for the JSON of the API and the reports: the number when finite, null when unknown (NaN) or
/// infinite. (Tracker logs and run comparisons spell NaN and infinities as strings instead, as protobuf's
/// JSON mapping does; they keep their own.)
inline nlohmann::json number_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

}  // namespace trailscope
