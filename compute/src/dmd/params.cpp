// DmdParams: ranges, messages and descriptions in one table, so that validate() and
// parameter_infos() cannot disagree.
#include <charconv>
#include <cmath>
#include <string>

#include "trailscope/core/error.hpp"
#include "trailscope/dmd/dmd.hpp"

namespace trailscope::dmd {
namespace {

// Shortest text that reads back to the same double ("0.001", "20").
std::string fmt(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

struct Range {
  const char* name;
  double lo, hi;
};
constexpr Range kLayers{"layers", 2, 256};
constexpr Range kMinGap{"min_gap", 1, 128};
constexpr Range kIsland{"island", 0, 0.1};
constexpr Range kSaliency{"saliency", 0, 100};

std::string range_text(const Range& r) {
  return "[" + fmt(r.lo) + ", " + fmt(r.hi) + "]";
}

void check(const Range& r, double v) {
  if (!(std::isfinite(v) && v >= r.lo && v <= r.hi))
    throw invalid_argument(r.name,
                           std::string(r.name) + " must be in " + range_text(r) + " (got " + fmt(v) + ")");
}

}  // namespace

void DmdParams::validate() const {
  check(kLayers, layers);
  if (selection != LayerSelection::cumulative && selection != LayerSelection::local_maxima)
    throw invalid_argument("selection", "selection must be cumulative or local_maxima");
  check(kMinGap, min_gap);
  check(kIsland, island);
  check(kSaliency, saliency);
}

const std::vector<ParamInfo>& parameter_infos() {
  static const std::vector<ParamInfo> infos = [] {
    const DmdParams d;
    return std::vector<ParamInfo>{
        {kLayers.name, "integer", std::to_string(d.layers), range_text(kLayers),
         "threshold layers including the canvas; 20-40 is DMD's usual range"},
        {"selection", "enum", to_string(d.selection), "cumulative | local_maxima",
         "how layer levels are picked from the histogram"},
        {kMinGap.name, "integer", std::to_string(d.min_gap), range_text(kMinGap) + " grey levels",
         "smallest difference between two layer levels (distinguishable interval)"},
        {kIsland.name, "number", fmt(d.island), range_text(kIsland) + " of the image area",
         "islands and holes smaller than this are removed from each layer"},
        {kSaliency.name, "number", fmt(d.saliency), range_text(kSaliency),
         "skeleton salience threshold (collapsed boundary length / distance to the boundary); 0 = exact"},
        {"interpolate", "boolean", d.interpolate ? "true" : "false", "true | false",
         "ramp between consecutive layers instead of flat bands"},
    };
  }();
  return infos;
}

const char* to_string(LayerSelection s) noexcept {
  return s == LayerSelection::local_maxima ? "local_maxima" : "cumulative";
}

const char* to_string(SegmentKind k) noexcept {
  switch (k) {
    case SegmentKind::peak:
      return "peak";
    case SegmentKind::junction:
      return "junction";
    default:
      return "canvas";
  }
}

LayerSelection parse_layer_selection(std::string_view text, const std::string& param) {
  if (text == "cumulative") return LayerSelection::cumulative;
  if (text == "local_maxima") return LayerSelection::local_maxima;
  throw invalid_argument(param,
                         param + " must be cumulative or local_maxima (got '" + std::string(text) + "')");
}

}  // namespace trailscope::dmd
