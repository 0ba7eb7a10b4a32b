#pragma once
// The congestion map of Klein, van der Zwan and Telea ("Dynamic multiscale visualization of flight data",
// VISAPP 2014): "a congestion map based on a thresholded version of our density map". Here the density
// is of simultaneous aircraft: how many aircraft are in a pixel at an instant, or on average over a
// window, with the pixels below a threshold left transparent and the others shaded by the number.
// Tiles follow the density tiles' conventions (density/canvas.hpp: XYZ Web Mercator on the 32-bit
// fixed-point grid, pixel (i, j) the half-open square [x0 + i·P, x0 + (i+1)·P) × [y0 + j·P, y0 + (j+1)·P))
// and reuse their shade stage (density/shade.hpp) and PNG encoder (density/png.hpp).
//
// The trajectory of a flight is the one trails/positions.hpp defines: latitude, longitude and altitude
// linear in time between consecutive samples of the flight (longitude the short way across 180°), across
// any gap inside a flight (flights are already split at long gaps on ingest), present from its first
// sample time to its last.
//
// INSTANT (`t`): the value of a pixel is the number of flights whose position at t (positions_at, with
// the query's filters) lies in the pixel. A pixel's edges are the meridians and parallels of its grid
// edges, in double precision: column i holds lon_i <= lon < lon_i+1 (longitude wrapped onto the canvas),
// row j holds lat_j+1 < lat <= lat_j (the half-open Mercator square; lat_j = unit_y_to_lat of the edge,
// geo/web_mercator.hpp). Positions beyond ±85.0511° are on no tile.
//
// WINDOW ([t0, t1)): the value is the time-weighted count, Σ over flights of the time the flight spends
// in the pixel during [t0, t1), divided by t1 − t0, which is the mean number of aircraft in the pixel
// over the window. The time in a pixel is exact: latitude and longitude are linear in time, Mercator
// columns are meridians and rows are parallels, so every pixel edge a segment crosses is crossed at a
// time solved in closed form, and the segment is cut there. Times are summed per pixel as whole
// microseconds (each piece rounded), so the result does not depend on the order of the additions or the
// number of threads. Filters apply to the trajectory at each instant: bbox and the altitude band exactly
// (the time a flight spends in the box and the band), on_ground by the earlier sample of each segment
// (as positions_at gives it), callsign and icao24 to the flight.
//
// THRESHOLD AND SHADING. Pixels whose value is below `threshold` (aircraft; a value of 0 always) are
// transparent. The others are shaded with the colormap by `how` (linear or log) between `threshold`
// (the first colour) and `vmax` (the last; values above clamp), the same span for every tile, so tiles
// never have seams; vmax defaults to 4 × threshold. The shading is density::shade with that fixed span.
#include <cstddef>
#include <optional>
#include <string>

#include "trailscope/density/canvas.hpp"
#include "trailscope/density/raster.hpp"
#include "trailscope/density/shade.hpp"
#include "trailscope/geo/tile_id.hpp"
#include "trailscope/trails/query.hpp"
#include "trailscope/trails/trail_set.hpp"

namespace trailscope::congestion {

/// Aircraft per pixel on `canvas` (inner area; its margin is ignored): at instant `t` when given (then
/// `q` must have neither t0 nor t1), else time-weighted over the query's window [t0, t1) (both required).
/// NaN where the value is 0. Throws invalid_argument naming "t" (not finite), "t0"/"t1" (a window and an
/// instant together, or neither: "give t, or t0 and t1").
density::Raster aircraft_per_pixel(const TrailSet& set, const Query& q, const density::Canvas& canvas,
                                   std::optional<double> t);

struct CongestionTileRequest {
  geo::TileId tile;
  int size = 256;              ///< limits::kTileSizeSmall or kTileSizeLarge
  std::optional<double> t;     ///< an instant, or nothing for the query's window
  double threshold = 1.0;      ///< aircraft per pixel, finite and > 0
  std::optional<double> vmax;  ///< the value of the last colour, > threshold; default 4 × threshold
  density::How how = density::How::linear;  ///< linear or log (eq_hist needs a distribution: refused)
  std::string cmap = "fire";
};

struct CongestionTile {
  std::string png;
  double max_value = 0;          ///< largest value of the tile (0 when empty)
  std::size_t pixels_above = 0;  ///< pixels at or above the threshold
};

/// Checks a request and its query without rendering: tile and size (as the density tiles), threshold,
/// vmax, how, cmap, and the instant or window as aircraft_per_pixel() does. Throws invalid_argument naming
/// "z", "x", "y", "size", "threshold", "vmax", "how", "cmap", "t", "t0" or "t1".
void validate(const CongestionTileRequest& r, const Query& q);

/// The thresholded congestion tile. Throws what validate() and aircraft_per_pixel() throw.
CongestionTile render_congestion_tile(const TrailSet& set, const Query& q, const CongestionTileRequest& r);

}  // namespace trailscope::congestion
