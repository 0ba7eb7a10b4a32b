#pragma once
// JSON text for the wire and for files. Messages can quote input bytes that are not UTF-8 (a damaged
// upload, a field of binary junk); nlohmann::json::dump() throws on those, so every serialisation goes
// through here and replaces them with U+FFFD instead.
#include <string>

#include <nlohmann/json.hpp>

namespace trailscope {

/// `j` as JSON text; `indent` < 0 gives the compact form. Never throws on invalid UTF-8.
inline std::string json_text(const nlohmann::json& j, int indent = -1) {
  return j.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace trailscope
