#pragma once
// SpanStats: the value range (and, for eq_hist, the value distribution) that `shade` normalises against.
// Tiles must not be normalised one by one — a tile's own max would give every tile its own colour scale
// and seams at every tile edge — so, as Datashader's render_tiles does with one span per zoom level
// (datashader/tiles.py, calculate_zoom_level_stats), one SpanStats is computed per (dataset, query,
// value, zoom, kernel) from a coarse aggregate of the query's whole extent and shared by every tile of
// that zoom (DensityRenderer in renderer.hpp caches them).
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "trailscope/density/raster.hpp"

namespace trailscope::density {

/// How values are normalised before colouring (see shade.hpp).
enum class How { linear, log, eq_hist };
/// Parses "linear" | "log" | "eq_hist"; throws invalid_argument(param) otherwise.
How parse_how(std::string_view text, const std::string& param = "how");
const char* to_string(How h) noexcept;

/// At most this many (value, fraction) points are kept for eq_hist; more distinct values are reduced to
/// this many quantiles.
inline constexpr std::size_t kMaxCdfPoints = 4096;

struct SpanStats {
  bool empty = true;               ///< no data at all: everything normalises to 0
  double lo = 0, hi = 0;           ///< smallest and largest sample
  std::uint64_t samples = 0;       ///< data pixels the span was computed from
  std::vector<double> cdf_values;  ///< ascending distinct sample values (or quantiles), first lo, last hi
  std::vector<double> cdf;         ///< fraction of samples <= cdf_values[k]; last is 1

  /// `v` normalised to [0, 1] by `how` (see shade.hpp); NaN stays NaN.
  double normalize(double v, How how) const;
};

/// The span of every non-NaN value of `r`, each multiplied by `scale` (> 0) and then raised to at least
/// `floor` (renderer.hpp explains why counts estimated at a coarser zoom are scaled and floored at 1).
SpanStats compute_span(const Raster& r, double scale = 1.0, double floor = -1e300);

/// The same transformation applied to an existing span: every value v becomes max(v · scale, floor)
/// (values the floor merges keep the largest fraction). Equal to compute_span(r, scale, floor) when the
/// span kept all its distinct values; with quantiles it transforms the quantiles, as the map is monotone.
SpanStats rescale_span(const SpanStats& s, double scale, double floor = -1e300);

}  // namespace trailscope::density
