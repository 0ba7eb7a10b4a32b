#pragma once
// The legend of a density tile's colours: which data value each colour of the shading stands for, so that
// a legend can label its ticks in the data's units and follow the shading actually applied (for eq_hist
// the ticks are quantiles of the zoom level's shared span, not evenly spaced values).
//
// For n stops at positions t_k = k / (n − 1): the colour is the colormap entry shade() picks for a value
// normalised to t_k (round((min_level + t_k·(1 − min_level))·255), shade.hpp MINIMUM LEVEL), and the
// value is the smallest v in [lo, hi] with span.normalize(v, how) >= t_k (bisection to 1e-9 of the span,
// so normalize(value) equals t_k wherever the normalisation is continuous, and exceeds it only where an
// eq_hist step jumps over t_k: then the value is that step's).
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trailscope/density/span.hpp"

namespace trailscope::density {

struct LegendStop {
  double t = 0;       ///< position along the legend, [0, 1]
  double value = 0;   ///< data value (count: segment passes per pixel; altitude: m; speed: m/s)
  std::string color;  ///< "#rrggbb"
};

struct Legend {
  bool empty = true;      ///< no data under the query: no stops
  double lo = 0, hi = 0;  ///< the span's smallest and largest value
  std::vector<LegendStop> stops;
  nlohmann::json to_json() const;  ///< {"empty", "lo", "hi", "stops": [{"t", "value", "color"}]}
};

/// The legend of `span` shaded with `how`, `cmap` and `min_level`, with `stops` stops (at least 2; the
/// work is linear in them, so callers bound them: limits::kMaxLegendStops on the server). Throws
/// invalid_argument naming `stops`, `cmap` or `min_level`.
Legend legend(const SpanStats& span, How how, const std::string& cmap, double min_level, int stops);

}  // namespace trailscope::density
