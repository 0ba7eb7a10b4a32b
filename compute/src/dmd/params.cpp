// DmdParams: ranges, messages and descriptions in one table, so that validate() and
// parameter_infos() cannot disagree.
#include <charconv>
#include <cmath>
#include <string>

#include "trailscope/core/error.hpp"
#include "trailscope/core/text.hpp"
#include "trailscope/dmd/dmd.hpp"

namespace trailscope::dmd {
namespace {

struct Range {
  const char* name;
  double lo, hi;
};
constexpr Range kLayers{"layers", 2, 256};
constexpr Range kMinGap{"min_gap", 1, 128};
constexpr Range kIsland{"island", 0, 0.1};
constexpr Range kSaliency{"saliency", 0, 100};

std::string range_text(const Range& r) {
  return "[" + format_double(r.lo) + ", " + format_double(r.hi) + "]";
}

void check(const Range& r, double v) {
  if (!(std::isfinite(v) && v >= r.lo && v <= r.hi))
    throw invalid_argument(
        r.name, std::string(r.name) + " must be in " + range_text(r) + " (got " + format_double(v) + ")");
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
    // The numeric parameters also carry their range and default as numbers.
    const auto numeric = [](ParamInfo i, const Range& r, double def, bool integer) {
      i.default_number = def, i.min = r.lo, i.max = r.hi, i.integer = integer;
      return i;
    };
    return std::vector<ParamInfo>{
        numeric(describe_param(kLayers.name, "integer", std::to_string(d.layers), range_text(kLayers),
                               "threshold layers including the canvas; 20-40 is DMD's usual range"),
                kLayers, d.layers, true),
        describe_param("selection", "enum", to_string(d.selection), "cumulative | local_maxima",
                       "how layer levels are picked from the histogram"),
        numeric(describe_param(kMinGap.name, "integer", std::to_string(d.min_gap),
                               range_text(kMinGap) + " grey levels",
                               "smallest difference between two layer levels (distinguishable interval)"),
                kMinGap, d.min_gap, true),
        numeric(describe_param(kIsland.name, "number", format_double(d.island),
                               range_text(kIsland) + " of the image area",
                               "islands and holes smaller than this are removed from each layer"),
                kIsland, d.island, false),
        numeric(describe_param(kSaliency.name, "number", format_double(d.saliency), range_text(kSaliency),
                               "skeleton salience threshold (collapsed boundary length / distance to the "
                               "boundary); 0 = exact"),
                kSaliency, d.saliency, false),
        describe_param("interpolate", "boolean", d.interpolate ? "true" : "false", "true | false",
                       "ramp between consecutive layers instead of flat bands"),
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
