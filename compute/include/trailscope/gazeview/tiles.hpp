#pragma once
// Gaze density tiles in stimulus pixel space: the Datashader pipeline of the flight density tiles
// (density/: Canvas -> aggregate -> optional KDE -> shade -> PNG) on a non-geographic tile grid.
//
// THE GRID. The stimulus (width_px x height_px, origin top-left, y down) sits in the top-left corner of a
// square of side S = max(width_px, height_px). That square is the "world" of an XYZ grid: zoom z has
// 2^z x 2^z tiles of 256 px, tile 0/0/0 covers the whole square, x grows right, y grows down. Stimulus
// point (sx, sy) has grid units (floor(sx / S * 2^32), floor(sy / S * 2^32)), the same 32-bit fixed-point
// grid the flight tiles have on Web Mercator, so density::Canvas::for_tile gives a tile's exact pixel
// edges and the aggregate, KDE, crop, shade and PNG stages are the flight tiles' own functions.
//
// WHAT IS DRAWN. Points inside the stimulus (0 <= sx < width_px, 0 <= sy < height_px; anything else, e.g.
// gaze off the image, is not drawn), each adding its weight to its pixel of density::Aggregate::count:
// samples weigh 1; fixations weigh their duration rounded to whole ms, at least 1 (a one-sample fixation
// has duration 0 but was still looked at). Per-pixel sums saturate at 2^31 − 1. With kernel_radius > 0
// the aggregate is smoothed by density::kde_smooth on the tile grown by the radius (so neighbouring
// tiles stay seamless), then cropped. Pixels whose centre is outside the stimulus are transparent.
//
// THE SPAN (the colour scale shared by every tile of a zoom, density/span.hpp):
//  - without smoothing it is exact: the per-pixel sums of every non-empty pixel of the zoom's whole grid
//    (points binned by their pixel key at that zoom and sorted: O(N log N), no canvas is allocated);
//  - with smoothing, the smoothed whole grid at zoom L_s = min(z, 2) (at most 1024 px, density::
//    kSpanCanvasPx) with the radius scaled by 2^(L_s − z), its values scaled by 4^(L_s − z): a kernel
//    density is mass per pixel area, and a pixel at z has 4^(z − L_s) times less area. Exact for z <= 2.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "trailscope/density/canvas.hpp"
#include "trailscope/density/legend.hpp"
#include "trailscope/density/raster.hpp"
#include "trailscope/density/shade.hpp"
#include "trailscope/density/span.hpp"
#include "trailscope/gazeview/fixations.hpp"
#include "trailscope/geo/tile_id.hpp"

namespace trailscope::gazeview {

/// The stimulus a grid covers, px; both > 0 and finite.
struct Stimulus {
  double width_px = 0, height_px = 0;
  double side() const { return width_px > height_px ? width_px : height_px; }
};
/// Throws Error(invalid_argument, "width_px" / "height_px", ...) unless both sizes are finite, > 0 and
/// at most 1e6.
void validate(const Stimulus& s);

/// The stimulus the views of `recordings` (ascending indices into `ds`) draw on: the screen of the first of
/// them (geometry width_px x height_px), as the stimulus fills the screen (fixations.hpp). Throws
/// Error(unprocessable, "recording", "the filters select no recording") for an empty list,
/// Error(unprocessable, "width_px", "recording N gives no screen size in px (width_px, height_px)") when
/// that recording has none, and validate()'s errors.
Stimulus stimulus_of(const gaze::GazeDataset& ds, const std::vector<std::size_t>& recordings);

/// Weighted points in stimulus px.
struct GazePoints {
  std::vector<double> x, y;
  std::vector<double> weight;  ///< see WHAT IS DRAWN: 1 per sample, duration per fixation
  std::size_t size() const { return x.size(); }
};

/// What a tile draws.
enum class TileWhat { samples, fixations };
/// "samples" | "fixations"; throws invalid_argument(param) otherwise.
TileWhat parse_tile_what(std::string_view text, const std::string& param = "what");
const char* to_string(TileWhat w) noexcept;

/// The valid samples of the selected recordings in the window (gaze::window_samples; weight 1), or the
/// selected fixations (view_events with `max_events`; weight as above). Throws what pixel_recordings and
/// view_events throw; samples need no detector (and no physical geometry).
GazePoints gaze_points(const gaze::GazeDataset& ds, const gaze::GazeFilter& f, const gaze::EventParams& p,
                       TileWhat what, std::size_t max_events);

/// The deposit of one point: 1 for a sample; max(1, round(duration)) for a fixation, saturated at 2^31 − 1.
std::int32_t point_weight(double weight);

/// The tile canvas of `tile` (256 px, `margin_px` around it) on the stimulus grid.
density::Canvas tile_canvas(const geo::TileId& tile, int margin_px = 0);
/// The grid unit of stimulus coordinate `v` on a square of side `side` (floor(v / side · 2^32)).
std::int64_t grid_unit(double v, double side);

/// The aggregate of `points` on `canvas` (WHAT IS DRAWN): counts hold the weight sums.
density::Aggregate aggregate_points(const GazePoints& points, const Stimulus& stim,
                                    const density::Canvas& canvas);

struct StimulusTileRequest {
  geo::TileId tile;  ///< z in limits::kMinZoom..kMaxZoom, x and y in 0..2^z − 1
  density::How how = density::How::eq_hist;
  std::string cmap = "fire";
  double kernel_radius = 0;  ///< px of the tile, 0..limits::kMaxKernelRadiusPx
  /// Colormap position of the lowest value (shade.hpp MINIMUM LEVEL); unset: density::
  /// kDefaultCountMinLevel, as for flight counts.
  std::optional<double> min_level;
};
/// Throws invalid_argument naming `z`, `x`, `y`, `cmap`, `kernel_radius` or `min_level`.
void validate(const StimulusTileRequest& r);

/// The tile's numbers (256 x 256 raster, NaN = no data or outside the stimulus).
density::Raster tile_raster(const GazePoints& points, const Stimulus& stim, const StimulusTileRequest& r);
/// The zoom's shared span (THE SPAN).
density::SpanStats zoom_span(const GazePoints& points, const Stimulus& stim, int z, double kernel_radius);

struct StimulusTile {
  density::Image image;  ///< 256 x 256 RGBA
  std::string png;       ///< its PNG bytes
  bool empty = true;     ///< no pixel holds data
  double max_value = 0;  ///< largest pixel value of this tile (after smoothing), 0 when empty
};

/// Validates everything (stimulus, request, points: x, y, weight of equal length), then aggregates,
/// smooths, shades against zoom_span and encodes. Throws as validate() and density::shade do, and
/// Error(invalid_argument, "points", ...) for arrays of different lengths.
StimulusTile render_stimulus_tile(const GazePoints& points, const Stimulus& stim,
                                  const StimulusTileRequest& r);

/// The legend of the zoom's tiles (density::legend over zoom_span, with the request's how, cmap and
/// min level); x and y of the tile do not matter. `stops` >= 2.
density::Legend stimulus_legend(const GazePoints& points, const Stimulus& stim, const StimulusTileRequest& r,
                                int stops);

}  // namespace trailscope::gazeview
