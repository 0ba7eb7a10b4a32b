#include "params/query_params.hpp"

#include <charconv>
#include <cmath>

#include "trailscope/core/error.hpp"

namespace trailscope::server::params {

const std::vector<std::string>& query_keys() {
  static const std::vector<std::string> keys = {"bbox",     "t0",     "t1",       "alt_min",  "alt_max",
                                                "alt_unit", "icao24", "callsign", "on_ground"};
  return keys;
}

std::vector<std::string> with_query_keys(std::vector<std::string> extra) {
  extra.insert(extra.end(), query_keys().begin(), query_keys().end());
  return extra;
}

static std::int64_t parse_int(const std::string& text, const std::string& name, std::int64_t lo,
                              std::int64_t hi) {
  std::int64_t v = 0;
  auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || p != text.data() + text.size() || text.empty())
    throw invalid_argument(name, name + ": '" + text + "' is not an integer");
  if (v < lo || v > hi)
    throw invalid_argument(
        name, name + " must lie in " + std::to_string(lo) + ".." + std::to_string(hi) + ", got " + text);
  return v;
}

std::int64_t integer(const Request& req, const std::string& name, std::int64_t fallback, std::int64_t lo,
                     std::int64_t hi) {
  auto it = req.query.find(name);
  return it == req.query.end() ? fallback : parse_int(it->second, name, lo, hi);
}

double number(const Request& req, const std::string& name, double fallback) {
  auto it = req.query.find(name);
  if (it == req.query.end()) return fallback;
  const std::string& text = it->second;
  double v = 0;
  auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || p != text.data() + text.size() || text.empty() || !std::isfinite(v))
    throw invalid_argument(name, name + ": '" + text + "' is not a number");
  return v;
}

std::string text(const Request& req, const std::string& name, const std::string& fallback) {
  auto it = req.query.find(name);
  return it == req.query.end() ? fallback : it->second;
}

std::int64_t path_integer(const PathParams& p, const std::string& name, std::int64_t lo, std::int64_t hi) {
  return parse_int(p.at(name), name, lo, hi);
}

}  // namespace trailscope::server::params
