#include "trailscope/density/legend.hpp"

#include <cmath>
#include <cstdio>

#include "trailscope/core/error.hpp"
#include "trailscope/core/text.hpp"
#include "trailscope/density/colormap.hpp"

namespace trailscope::density {

Legend legend(const SpanStats& span, How how, const std::string& cmap, double min_level, int stops) {
  const Colormap& map = colormap(cmap, "cmap");
  if (stops < 2) throw invalid_argument("stops", "stops must be at least 2, got " + std::to_string(stops));
  if (!(min_level >= 0 && min_level < 1))
    throw invalid_argument("min_level", "min_level must lie in [0, 1), got " + format_double(min_level));
  Legend out;
  out.empty = span.empty;
  if (span.empty) return out;
  out.lo = span.lo, out.hi = span.hi;
  for (int k = 0; k < stops; ++k) {
    const double t = static_cast<double>(k) / (stops - 1);
    // The smallest value normalised to at least t: normalize is monotone on [lo, hi].
    double a = span.lo, b = span.hi;
    if (span.normalize(a, how) < t) {
      for (int it = 0; it < 200 && b - a > 1e-9 * std::max(1.0, span.hi - span.lo); ++it) {
        const double m = 0.5 * (a + b);
        (span.normalize(m, how) >= t ? b : a) = m;
      }
      a = b;
    }
    const auto& c =
        map.rgb[static_cast<std::size_t>(std::lround((min_level + t * (1.0 - min_level)) * 255.0))];
    char hex[8];
    std::snprintf(hex, sizeof hex, "#%02x%02x%02x", c[0], c[1], c[2]);
    out.stops.push_back({t, a, hex});
  }
  return out;
}

nlohmann::json Legend::to_json() const {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& s : stops) list.push_back({{"t", s.t}, {"value", s.value}, {"color", s.color}});
  return {{"empty", empty}, {"lo", lo}, {"hi", hi}, {"stops", std::move(list)}};
}

}  // namespace trailscope::density
