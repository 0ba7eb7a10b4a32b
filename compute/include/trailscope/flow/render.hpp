#pragma once
// Drawing a flow map at a continuous abstraction level L in [0, 2] (van der Zwan, Telea, Isenberg,
// "Continuous navigation of nested abstraction levels", EuroVis 2012 short papers): the levels are
// interpolated, and two neighbouring levels are shown at once, blended through a distance-field halo.
//
// EXACTLY WHAT IS DRAWN (all lengths in output pixels; the image is nx·cell_px × ny·cell_px, a cell of
// the field being cell_px × cell_px pixels):
//  1. Geometry: FlowMap::lines_at(L) (streamlines for L <= 1; for L in (1, 2] CUBu's relaxation toward
//     them, relaxation 2 − L, so the lines slide continuously into their bundles).
//  2. Per line, t = line_traffic / the largest line_traffic; width = line_width·(0.5 + 1.5·√t), alpha =
//     0.25 + 0.75·√t; lines drawn in order of increasing traffic (the main flows on top). Colour per
//     segment: hue = its compass heading/360 (north red, east yellow-green, south cyan-blue, west
//     purple), saturation 0.85, value 1 (bundling::hsv_to_rgb). A line covers a pixel once, with its
//     segment nearest to the pixel centre, coverage clamp(width/2 + 0.5 − distance, 0, 1).
//  3. The lines layer has opacity a1 = min(L, 1); the density layer (the `base` image: the line density
//     of the same traffic, density/renderer.hpp, or the shaded traffic of an uploaded field) has opacity
//     a0 = max(0, 1 − L) times the HALO factor clamp(D/(halo_px·min(L, 1)), 0, 1), D the Euclidean
//     distance (px) to the nearest pixel a line covers by at least 0.5: while L grows from 0 to 1 the
//     density first clears around the lines (focus) and keeps its context further away, then fades.
//  4. Over the background (black: opaque; transparent: straight alpha, for a map layer): density, then
//     lines, "over" compositing in premultiplied float, rounded to 8 bits.
// Deterministic: the same map, base and parameters give the same bytes.
#include <string>
#include <string_view>
#include <utility>

#include "trailscope/density/shade.hpp"
#include "trailscope/flow/flow_map.hpp"
#include "trailscope/geo/tile_id.hpp"
#include "trailscope/trails/query.hpp"
#include "trailscope/trails/trail_set.hpp"

namespace trailscope::flow {

struct FlowRenderParams {
  double level = 2;                  ///< abstraction level, 0 density .. 1 streamlines .. 2 bundled
  int cell_px = 4;                   ///< output pixels per field cell; 1..16 (image ≤ kMaxFlowImagePx)
  double line_width = 1.5;           ///< px of the heaviest line's half-weight; 0.25..8
  double halo_px = 6;                ///< halo radius at level 1, px; 0..64
  std::string background = "black";  ///< black | transparent
  std::string cmap = "fire";         ///< colour map of the density level (density/colormap.hpp)
  /// Throws invalid_argument naming `level`, `cell_px`, `line_width`, `halo_px`, `background` or `cmap`.
  void validate() const;
  /// The output size for `map`; throws Error(payload_too_large, `cell_px`) beyond kMaxFlowImagePx.
  std::pair<int, int> size(const FlowMap& map) const;
  std::pair<int, int> size(const Grid& grid) const;
  /// Sets `level`, `cell_px`, `line_width`, `halo_px`, `background` or `cmap` from text; returns false
  /// for another name; throws invalid_argument(name) for a bad value, leaving the params unchanged.
  bool set(std::string_view name, std::string_view value);
};

/// Sets one flow option by name: a FlowRenderParams name, else FlowParams::set (field, streamline and
/// `bundle.<name>` parameters). Throws invalid_argument(name) for an unknown name or a bad value. The
/// CLI's flags and the route's query parameters both go through it.
void set_flow_option(FlowParams& params, FlowRenderParams& render, std::string_view name,
                     std::string_view value);

/// The density level of a traffic flow map: density::render_canvas of `trails` under `query` (counts,
/// eq_hist, params.cmap, segments longer than the field's max gap not drawn) on the canvas of the
/// map's grid at cell_px pixels per cell (pixel units = cell/cell_px rounded). Throws
/// Error(unprocessable, `grid`) for a map without a geographic grid, and what render_canvas throws.
density::Image traffic_base(const TrailSet& trails, const Query& query, const FlowMap& map,
                            const FlowRenderParams& params, double max_gap_seconds);
/// The density level of any flow map: the total traffic of its field (total_traffic), interpolated
/// bilinearly from the cell centres to every pixel, shaded with eq_hist and params.cmap (0 = no data).
density::Image field_base(const FlowMap& map, const FlowRenderParams& params);

struct FlowImage {
  FlowMap map;
  density::Image image;
  double render_ms = 0;
};
/// A flight dataset's flow map drawn, in one call (the CLI's `flow` verb and the flow route): the grid
/// first, then the cost checks (FlowParams::check_cost, the image size) BEFORE any point is read, then
/// flow_map, traffic_base and render_flow. Throws what those throw.
FlowImage flow_image(const TrailSet& trails, const Query& query, const FlowParams& params,
                     const FlowRenderParams& render, Backend backend = default_backend(),
                     const ProgressFn& progress = {}, const CancelToken* cancel = nullptr);
/// The same for an uploaded field (parse_field), its density level drawn by field_base.
FlowImage flow_image(VectorField field, const FlowParams& params, const FlowRenderParams& render,
                     Backend backend = default_backend(), const ProgressFn& progress = {},
                     const CancelToken* cancel = nullptr);

/// Draws `map` at params.level over `base` (which must have params.size(map); invalid_argument(`base`)
/// otherwise). Throws as FlowRenderParams::validate and FlowMap::lines_at.
density::Image render_flow(const FlowMap& map, const density::Image& base, const FlowRenderParams& params);

/// One XYZ map tile of a flow map on a geographic grid: the tile grid of the density tiles (Web Mercator,
/// geo/tile_id.hpp; tile (z, x, y) covers 32-bit Mercator units [x·2^(32−z), (x+1)·2^(32−z)) in x and the
/// same in y, `size` pixels a side), holding the LINES layer of render_flow at params.level (step 2 above:
/// lines_at(level), widths params.line_width in tile pixels, colour by heading, opacity min(level, 1)) over
/// a transparent background, straight alpha. The density level and its halo are not in it: on a map the
/// density tiles are that level, drawn under these at opacity 1 − level. cell_px, halo_px, background and
/// cmap are not used (the tile's zoom sets the scale).
/// SEAMLESS. Each pixel is computed from the lines and its own Mercator position only, exactly as
/// render_flow computes a pixel of the whole view (the lines of every segment that reaches the tile,
/// widened by its half width, are drawn; the others are skipped after a bounds test), so neighbouring
/// tiles join without a seam, and where a tile's pixels coincide with the whole view's (cell_px pixels of
/// the view = one cell = a whole number of tile pixels, the grid's corner on a tile pixel) the bytes are
/// the same as render_flow with a transparent background at level >= 1. A grid that runs past 180° east
/// is drawn in every copy of the world the tile sees. A tile the grid does not reach is transparent.
/// Throws invalid_argument as FlowRenderParams::validate and geo::validate_tile (`z`, `x`, `y`),
/// invalid_argument(`size`) unless size is limits::kTileSizeSmall or kTileSizeLarge, and
/// Error(unprocessable, `grid`) for a map without a geographic grid.
density::Image render_flow_tile(const FlowMap& map, const geo::TileId& tile, int size,
                                const FlowRenderParams& params);

}  // namespace trailscope::flow
