#pragma once
// Canvas: the pixel grid a density image is aggregated on, the first stage of the Datashader pipeline
// (Canvas → aggregate → shade; Bednar et al., datashader.org, "Pipeline"). Unlike Datashader's float
// x/y ranges, a TrailScope canvas lives on the 32-bit fixed-point Web Mercator grid
// (geo/web_mercator.hpp): square pixels of an integer number of units, an integer origin. That makes
// a tile's pixel edges exact integers, so that the same trail gives the same pixels whichever tile or
// canvas it is drawn on (the seam guarantee of density_lines.hpp).
//
// A canvas may carry a margin of `margin` pixels on every side beyond its "inner" area (for KDE
// smoothing that must see data from neighbouring tiles); width()/height() include the margin.
// Coordinates may extend beyond the world in x (a margin at 180°, or a box across the antimeridian):
// data is drawn there wrapped around the world.
#include <cstdint>
#include <string>

#include "trailscope/geo/tile_id.hpp"

namespace trailscope::density {

/// Largest canvas edge (pixels, margin included). 8192² int32 counts are 256 MiB.
inline constexpr int kMaxCanvasPx = 8192;
/// Largest pixel size (32-bit Mercator units): a 16 px wide world. Bounds the walk's integers
/// (density_lines.hpp) well inside int64.
inline constexpr std::int64_t kMaxPixelUnits = std::int64_t{1} << 28;
/// Largest margin of a tile canvas (pixels); KDE needs at most limits::kMaxKernelRadiusPx.
inline constexpr int kMaxMarginPx = 256;

class Canvas {
 public:
  /// A canvas whose pixel (0, 0) has its north-west corner at (origin_x, origin_y) in 32-bit Mercator
  /// units, with square pixels of `pixel_units` units, `width` × `height` pixels including a margin of
  /// `margin` pixels on each side. Throws invalid_argument naming `width`, `height`, `pixel_units`,
  /// `margin` or `origin` when a value is out of range (sizes 1..kMaxCanvasPx, pixel_units
  /// 1..kMaxPixelUnits, 2·margin < width and height, origin within ±2^34).
  Canvas(std::int64_t origin_x, std::int64_t origin_y, std::int64_t pixel_units, int width, int height,
         int margin = 0);

  /// The canvas of XYZ tile `tile` at `size_px` × `size_px` pixels plus `margin_px` on each side.
  /// size_px must be a power of two from 1 to 4096 that divides the tile's 2^(32−z) units; margin_px in
  /// 0..kMaxMarginPx. Throws invalid_argument naming `z`/`x`/`y` (validate_tile), `size` or `margin`.
  static Canvas for_tile(const geo::TileId& tile, int size_px, int margin_px = 0);

  /// A canvas covering a longitude/latitude box (degrees; west > east crosses 180°) `width_px` pixels
  /// wide, with square pixels and the height that follows (≥ 1). The pixel size is rounded up to whole
  /// units, so the canvas may reach a fraction of a pixel beyond the box east and south. Throws
  /// invalid_argument naming `bbox` (empty or inverted latitudes) or `width`/`height`.
  static Canvas for_bbox(const geo::LonLatBox& box, int width_px, int margin_px = 0);

  /// The canvas covering `box` on the pixel grid of zoom `z` with tiles of `tile_px` pixels (pixel edges
  /// aligned with that zoom's tiles; whole pixels, so it may exceed the box by up to one pixel on each
  /// side). Throws invalid_argument naming `bbox`, `z` or `width`/`height` (more than kMaxCanvasPx).
  static Canvas for_zoom(const geo::LonLatBox& box, int z, int tile_px = 256, int margin_px = 0);

  int width() const { return width_; }
  int height() const { return height_; }
  int margin() const { return margin_; }
  int inner_width() const { return width_ - 2 * margin_; }
  int inner_height() const { return height_ - 2 * margin_; }
  std::int64_t origin_x() const { return origin_x_; }
  std::int64_t origin_y() const { return origin_y_; }
  std::int64_t pixel_units() const { return pixel_units_; }
  /// One past the east / south edge, in units.
  std::int64_t end_x() const { return origin_x_ + pixel_units_ * width_; }
  std::int64_t end_y() const { return origin_y_ + pixel_units_ * height_; }

  /// The same grid without its margin.
  Canvas inner() const;
  /// The same grid grown by `margin_px` pixels on each side (margins add up).
  Canvas with_margin(int margin_px) const;

  /// Longitude/latitude bounds of the inner area (degrees; longitudes not wrapped, so a canvas across
  /// 180° has east > 180).
  geo::LonLatBox bounds() const;
  /// "origin=(x,y) px=units size=WxH margin=m", for messages.
  std::string describe() const;

  bool operator==(const Canvas&) const = default;

 private:
  std::int64_t origin_x_, origin_y_, pixel_units_;
  int width_, height_, margin_;
};

}  // namespace trailscope::density
