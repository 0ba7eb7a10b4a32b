#include "params/congestion_body.hpp"

#include <algorithm>
#include <map>

#include "params/json_fields.hpp"
#include "params/query_params.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::server {

namespace {
/// The parts a request may compute, in the order the result lists them.
const std::vector<std::string> kParts = {"occupancy", "entries", "hotspots", "complexity", "separation"};

/// Copies the fields of object `obj` (named `where` in errors) into `params`, each as a parameter
/// parser reads it: only `allowed` keys; null means absent.
void copy_fields(const nlohmann::json& obj, const std::string& where, const std::vector<std::string>& allowed,
                 std::map<std::string, std::string>& params) {
  if (!obj.is_object()) throw invalid_argument(where, where + ": must be an object");
  reject_unknown_fields(obj, allowed, where);
  for (const auto& [k, v] : obj.items())
    if (!v.is_null()) params[k] = scalar_text(v, k);
}
}  // namespace

std::vector<std::string> CongestionRequest::compute() const {
  std::vector<std::string> out;
  const bool on[] = {occupancy, entries, hotspots, complexity, separation};
  for (std::size_t i = 0; i < kParts.size(); ++i)
    if (on[i]) out.push_back(kParts[i]);
  return out;
}

CongestionRequest parse_congestion_request(const nlohmann::json& j) {
  if (!j.is_object())
    throw invalid_argument("body",
                           "body: a JSON object {\"dataset\": ..., \"query\": ..., \"volumes\": ...} is "
                           "required");
  reject_unknown_fields(j,
                        {"dataset", "query", "volumes", "compute", "step", "duration", "method",
                         "entry_window", "entry_step", "thresholds", "complexity_params"},
                        "the body");
  CongestionRequest r;
  r.dataset = string_field(j, "dataset");
  std::map<std::string, std::string> params;

  // The window: t0 and t1 (required by the counts' parser, which names them), and the flight filters.
  if (const auto q = j.find("query"); q != j.end()) {
    if (!q->is_object()) throw invalid_argument("query", "query: must be an object of window filters");
    const auto& keys = params::query_keys();
    for (const auto& [k, v] : q->items()) {
      if (k == "bbox" || k == "alt_min" || k == "alt_max" || k == "alt_unit")
        throw invalid_argument(k, k + ": the extent of the grid goes in volumes.grid, not in query (sectors "
                                      "have their own)");
      if (std::find(keys.begin(), keys.end(), k) == keys.end())
        throw invalid_argument(k, "unknown query parameter '" + k + "'");
      if (!v.is_null()) params[k] = scalar_text(v, k);
    }
  }

  // The volumes: the grid over an extent, or a stored sector set.
  const auto vol = j.find("volumes");
  if (vol == j.end() || !vol->is_object() || vol->size() != 1 ||
      (!vol->contains("grid") && !vol->contains("sectors")))
    throw invalid_argument("volumes",
                           "volumes: an object {\"grid\": {\"bbox\", \"alt_min\", \"alt_max\"}} or "
                           "{\"sectors\": \"<id>\"} is required");
  r.volumes = *vol;
  if (const auto g = vol->find("grid"); g != vol->end()) {
    if (g->is_null())
      throw invalid_argument("grid", "grid: must be an object (may be empty: the whole world)");
    nlohmann::json grid = *g;
    // bbox as [w, s, e, n] or the query's "w,s,e,n".
    if (const auto b = grid.find("bbox"); b != grid.end() && b->is_array()) {
      std::string text;
      for (const auto& x : *b) {
        if (!x.is_number())
          throw invalid_argument("bbox", "bbox: must be [west, south, east, north] in degrees");
        text += (text.empty() ? "" : ",") + scalar_text(x, "bbox");
      }
      *b = text;
    }
    copy_fields(grid, "grid", {"bbox", "alt_min", "alt_max", "alt_unit"}, params);
  } else {
    const auto& s = vol->at("sectors");
    if (!s.is_string() || s.get<std::string>().empty())
      throw invalid_argument("sectors",
                             "sectors: must be the id of a stored sector set (POST /api/v1/sectors)");
    r.sectors = s.get<std::string>();
  }

  // What to compute.
  if (const auto c = j.find("compute"); c != j.end()) {
    const std::string expected =
        "compute: must be a non-empty array of occupancy, entries, hotspots, complexity, "
        "separation";
    if (!c->is_array() || c->empty()) throw invalid_argument("compute", expected);
    r.occupancy = r.entries = r.hotspots = r.complexity = r.separation = false;
    for (const auto& part : *c) {
      if (!part.is_string()) throw invalid_argument("compute", expected);
      const std::string p = part.get<std::string>();
      if (p == "occupancy")
        r.occupancy = true;
      else if (p == "entries")
        r.entries = true;
      else if (p == "hotspots")
        r.hotspots = true;
      else if (p == "complexity")
        r.complexity = true;
      else if (p == "separation")
        r.separation = true;
      else
        throw invalid_argument("compute", "compute: unknown part '" + p +
                                              "' (occupancy, entries, hotspots, "
                                              "complexity or separation)");
    }
  }

  // Counting periods, entry windows, thresholds and the complexity parameters, as the counts' parser reads
  // them.
  for (const char* k : {"step", "duration", "method", "entry_window", "entry_step"})
    if (const auto v = j.find(k); v != j.end() && !v->is_null()) params[k] = scalar_text(*v, k);
  if (const auto t = j.find("thresholds"); t != j.end() && !t->is_null()) {
    if (!r.hotspots)
      throw invalid_argument("thresholds", "thresholds: they make hotspots, which compute does not list");
    copy_fields(*t, "thresholds", {"peak", "sustained", "sustained_steps"}, params);
  }
  if (const auto cp = j.find("complexity_params"); cp != j.end() && !cp->is_null()) {
    if (!r.complexity)
      throw invalid_argument("complexity_params",
                             "complexity_params: they apply to complexity, which compute does not list");
    copy_fields(*cp, "complexity_params", {"heading_deg", "speed_kt", "vrate_fpm"}, params);
  }
  params["complexity"] = r.complexity ? "true" : "false";
  r.counts = congestion::parse_counts_request(params);
  return r;
}

}  // namespace trailscope::server
