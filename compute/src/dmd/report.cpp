#include "trailscope/dmd/report.hpp"

namespace trailscope::dmd {

nlohmann::json to_json(const DmdResult& r, const DmdParams& p) {
  nlohmann::json layers = nlohmann::json::array();
  for (const auto& l : r.layers)
    layers.push_back({{"level", l.level},
                      {"threshold_pixels", l.threshold_pixels},
                      {"islands_removed", l.islands.islands_removed},
                      {"holes_filled", l.islands.holes_filled},
                      {"medial_axis_pixels", l.medial_axis_pixels},
                      {"skeleton_pixels", l.skeleton_pixels},
                      {"reconstructed_pixels", l.reconstructed_pixels}});
  nlohmann::json segments = nlohmann::json::array();
  for (const auto& s : r.segments)
    segments.push_back({{"label", s.label},
                        {"kind", to_string(s.kind)},
                        {"area", s.area},
                        {"centroid", {s.cx, s.cy}},
                        {"mean_value", s.mean_value},
                        {"bbox", {s.x0, s.y0, s.x1, s.y1}},
                        {"top_level", s.top_level},
                        {"base_level", s.base_level}});
  const StageTimes& t = r.times;
  return {{"params",
           {{"layers", p.layers},
            {"selection", to_string(p.selection)},
            {"min_gap", p.min_gap},
            {"island", p.island},
            {"saliency", p.saliency},
            {"interpolate", p.interpolate}}},
          {"levels", r.levels},
          {"layers_used", r.levels.size()},
          {"layers", layers},
          {"skeleton_pixels", r.skeleton_pixels},
          {"medial_axis_pixels", r.medial_axis_pixels},
          {"times_ms",
           {{"select", t.select_ms},
            {"threshold", t.threshold_ms},
            {"islands", t.islands_ms},
            {"skeleton", t.skeleton_ms},
            {"simplify", t.simplify_ms},
            {"reconstruct", t.reconstruct_ms},
            {"stack", t.stack_ms},
            {"segment", t.segment_ms},
            {"total", t.total_ms}}},
          {"segments", segments}};
}

}  // namespace trailscope::dmd
