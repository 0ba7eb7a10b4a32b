// Presentation of a MetricsReport: JSON for the API/CLI and TrackEval's text tables for humans.
#include <cmath>
#include <cstdio>
#include <algorithm>
#include <map>

#include "trailscope/core/json_text.hpp"
#include "trailscope/metrics/evaluate.hpp"

namespace trailscope::metrics {
namespace {

/// JSON has no NaN; "no value" (no matches, no consecutive matches) is null.
const char* error_unit(const MetricsReport& r) {
  return r.kind == SimilarityKind::iou ? "1 - IoU" : "distance";
}

/// TrackEval prints ratios as percentages with 5 significant digits and counts as integers.
std::string cell(double v, bool is_count) {
  char buf[32];
  if (is_count)
    std::snprintf(buf, sizeof buf, "%.0f", v);
  else
    std::snprintf(buf, sizeof buf, "%1.5g", 100.0 * v);
  return buf;
}

void table(std::string& out, const std::string& family, const std::string& name,
           const std::vector<std::pair<std::string, double>>& cols, const std::vector<std::string>& fields,
           const std::vector<std::string>& counts) {
  std::map<std::string, double> by_name(cols.begin(), cols.end());
  char buf[64];
  std::snprintf(buf, sizeof buf, "%-35s", (family + ": " + name).c_str());
  out += buf;
  for (const auto& f : fields) {
    // The curves are shown by their mean, under the curve's own name as TrackEval's summary does.
    const std::string label = f.ends_with("___AUC") ? f.substr(0, f.size() - 6) : f;
    std::snprintf(buf, sizeof buf, "%-12s", label.c_str());
    out += buf;
  }
  out += "\n";
  std::snprintf(buf, sizeof buf, "%-35s", name.c_str());
  out += buf;
  for (const auto& f : fields) {
    const bool is_count = std::find(counts.begin(), counts.end(), f) != counts.end();
    std::snprintf(buf, sizeof buf, "%-12s", cell(by_name.at(f), is_count).c_str());
    out += buf;
  }
  out += "\n\n";
}

}  // namespace

nlohmann::json to_json(const MetricsReport& r, bool details) {
  nlohmann::json j;
  j["similarity"] = r.kind == SimilarityKind::iou ? "iou" : "distance";
  if (r.kind == SimilarityKind::distance) j["d_max"] = r.d_max;
  j["ms"] = r.ms;
  nlohmann::json m = nlohmann::json::object();
  for (const auto& [name, v] : trackeval_columns(r)) m[name] = number_or_null(v);
  j["metrics"] = std::move(m);
  j["extras"] = {{"mean_error", number_or_null(r.clear.mean_error)},
                 {"jitter", number_or_null(r.clear.jitter)},
                 {"lost_episodes", r.clear.lost_episodes},
                 {"error_unit", error_unit(r)}};
  if (!details) return j;
  auto& frames = j["per_frame"] = nlohmann::json::array();
  for (const auto& f : r.clear.frames)
    frames.push_back({{"frame", f.frame},
                      {"gt", f.gt},
                      {"trk", f.trk},
                      {"tp", f.tp},
                      {"fn", f.fn},
                      {"fp", f.fp},
                      {"idsw", f.idsw},
                      {"mean_error", number_or_null(f.mean_error)}});
  auto& targets = j["per_target"] = nlohmann::json::array();
  for (const auto& t : r.clear.targets)
    targets.push_back({{"id", t.id},
                       {"first_frame", t.first_frame},
                       {"last_frame", t.last_frame},
                       {"frames", t.frames},
                       {"matched", t.matched},
                       {"tracked_ratio", t.tracked_ratio},
                       {"coverage", t.coverage},
                       {"idsw", t.idsw},
                       {"frag", t.frag},
                       {"lost_episodes", t.lost_episodes},
                       {"mean_error", number_or_null(t.mean_error)},
                       {"jitter", number_or_null(t.jitter)},
                       {"jitter_pairs", t.jitter_pairs}});
  auto& pairs = j["identity_pairs"] = nlohmann::json::array();
  for (const auto& p : r.identity.pairs)
    pairs.push_back({{"gt_id", p.gt_id}, {"trk_id", p.trk_id}, {"idtp", p.idtp}});
  return j;
}

std::string to_table(const MetricsReport& r, const std::string& name) {
  const auto cols = trackeval_columns(r);
  std::string out;
  table(out, "HOTA", name, cols,
        {"HOTA___AUC", "DetA___AUC", "AssA___AUC", "DetRe___AUC", "DetPr___AUC", "AssRe___AUC", "AssPr___AUC",
         "LocA___AUC", "RHOTA___AUC", "HOTA(0)", "LocA(0)", "HOTALocA(0)"},
        {});
  table(out, "CLEAR", name, cols,
        {"MOTA", "MOTP", "MODA", "CLR_Re", "CLR_Pr", "MTR", "PTR", "MLR", "sMOTA", "CLR_TP", "CLR_FN",
         "CLR_FP", "IDSW", "MT", "PT", "ML", "Frag"},
        {"CLR_TP", "CLR_FN", "CLR_FP", "IDSW", "MT", "PT", "ML", "Frag"});
  table(out, "Identity", name, cols, {"IDF1", "IDR", "IDP", "IDTP", "IDFN", "IDFP"},
        {"IDTP", "IDFN", "IDFP"});
  table(out, "Count", name, cols, {"Dets", "GT_Dets", "IDs", "GT_IDs"}, {"Dets", "GT_Dets", "IDs", "GT_IDs"});
  char buf[256];
  std::snprintf(buf, sizeof buf, "Extras: mean error %.4g (%s), jitter %.4g, lost episodes %ld\n",
                r.clear.mean_error, error_unit(r), r.clear.jitter, r.clear.lost_episodes);
  out += buf;
  return out;
}

}  // namespace trailscope::metrics
