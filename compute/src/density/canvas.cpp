#include "trailscope/density/canvas.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

#include "trailscope/core/error.hpp"
#include "trailscope/geo/web_mercator.hpp"

namespace trailscope::density {
namespace {

constexpr double kWorld = 4294967296.0;  // 2^32
constexpr std::int64_t kMaxOrigin = std::int64_t{1} << 34;

// Fixed-point x extent [x_west, x_east) of a box, x_east > x_west; a box across 180° (west > east)
// ends beyond 2^32, and west = -180, east = 180 covers exactly the world.
void box_units(const geo::LonLatBox& box, double& xw, double& xe, double& yn, double& ys) {
  if (!std::isfinite(box.west) || !std::isfinite(box.east) || !std::isfinite(box.south) ||
      !std::isfinite(box.north))
    throw invalid_argument("bbox", "bounding box has a non-finite coordinate");
  if (box.south < -90 || box.north > 90 || !(box.south < box.north))
    throw invalid_argument("bbox", "bounding box needs -90 <= south < north <= 90");
  double span = box.east - box.west;
  if (span <= 0) span += 360.0;
  if (span <= 0 || span > 360.0)
    throw invalid_argument("bbox", "bounding box longitudes span nothing or more than 360°");
  xw = geo::lon_to_unit_x(box.west) * kWorld;
  xe = xw + span / 360.0 * kWorld;
  yn = geo::lat_to_unit_y(box.north) * kWorld;
  ys = geo::lat_to_unit_y(box.south) * kWorld;
  if (!(ys > yn))
    throw invalid_argument("bbox", "bounding box is empty after clamping latitudes to ±85.0511°");
}

}  // namespace

Canvas::Canvas(std::int64_t origin_x, std::int64_t origin_y, std::int64_t pixel_units, int width, int height,
               int margin)
    : origin_x_(origin_x),
      origin_y_(origin_y),
      pixel_units_(pixel_units),
      width_(width),
      height_(height),
      margin_(margin) {
  if (width < 1 || width > kMaxCanvasPx)
    throw invalid_argument("width", "canvas width " + std::to_string(width) + " px is outside 1.." +
                                        std::to_string(kMaxCanvasPx));
  if (height < 1 || height > kMaxCanvasPx)
    throw invalid_argument("height", "canvas height " + std::to_string(height) + " px is outside 1.." +
                                         std::to_string(kMaxCanvasPx));
  if (pixel_units < 1 || pixel_units > kMaxPixelUnits)
    throw invalid_argument("pixel_units", "pixel size of " + std::to_string(pixel_units) +
                                              " Mercator units is outside 1..2^28 (a canvas at least 16 px "
                                              "across the world)");
  if (margin < 0 || 2 * margin >= width || 2 * margin >= height)
    throw invalid_argument("margin", "margin " + std::to_string(margin) + " px does not fit a " +
                                         std::to_string(width) + "x" + std::to_string(height) + " canvas");
  if (origin_x < -kMaxOrigin || origin_x > kMaxOrigin || origin_y < -kMaxOrigin || origin_y > kMaxOrigin)
    throw invalid_argument("origin", "canvas origin is further than 2^34 units from the world");
}

Canvas Canvas::for_tile(const geo::TileId& tile, int size_px, int margin_px) {
  geo::validate_tile(tile);
  if (size_px < 1 || size_px > 4096 || (size_px & (size_px - 1)) != 0)
    throw invalid_argument("size",
                           "tile size " + std::to_string(size_px) + " px is not a power of two in 1..4096");
  const std::int64_t units = geo::tile_size_units(tile.z);
  if (units % size_px != 0)
    throw invalid_argument("size", "tile size " + std::to_string(size_px) +
                                       " px is finer than the 32-bit grid at zoom " + std::to_string(tile.z));
  if (margin_px < 0 || margin_px > kMaxMarginPx)
    throw invalid_argument("margin", "margin " + std::to_string(margin_px) + " px is outside 0.." +
                                         std::to_string(kMaxMarginPx));
  const std::int64_t p = units / size_px;
  return Canvas(geo::tile_origin_x(tile) - margin_px * p, geo::tile_origin_y(tile) - margin_px * p, p,
                size_px + 2 * margin_px, size_px + 2 * margin_px, margin_px);
}

Canvas Canvas::for_bbox(const geo::LonLatBox& box, int width_px, int margin_px) {
  double xw, xe, yn, ys;
  box_units(box, xw, xe, yn, ys);
  if (width_px < 1 || width_px > kMaxCanvasPx)
    throw invalid_argument("width", "canvas width " + std::to_string(width_px) + " px is outside 1.." +
                                        std::to_string(kMaxCanvasPx));
  const std::int64_t p =
      std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil((xe - xw) / width_px)));
  if (p > kMaxPixelUnits)
    throw invalid_argument("width", "canvas is too narrow for this box (under 16 px per world)");
  const auto height = static_cast<std::int64_t>(std::ceil((ys - yn) / static_cast<double>(p)));
  if (height > kMaxCanvasPx)
    throw invalid_argument("height", "the box needs a canvas " + std::to_string(height) +
                                         " px high at this width (max " + std::to_string(kMaxCanvasPx) + ")");
  const auto ox = static_cast<std::int64_t>(std::floor(xw));
  const auto oy = static_cast<std::int64_t>(std::floor(yn));
  return Canvas(ox - margin_px * p, oy - margin_px * p, p, width_px + 2 * margin_px,
                static_cast<int>(std::max<std::int64_t>(1, height)) + 2 * margin_px, margin_px);
}

Canvas Canvas::for_zoom(const geo::LonLatBox& box, int z, int tile_px, int margin_px) {
  if (tile_px < 1 || tile_px > 4096 || (tile_px & (tile_px - 1)) != 0)
    throw invalid_argument("size",
                           "tile size " + std::to_string(tile_px) + " px is not a power of two in 1..4096");
  const int log2_tile = std::countr_zero(static_cast<unsigned>(tile_px));
  if (z < 0 || z + log2_tile > 32)
    throw invalid_argument("z", "zoom " + std::to_string(z) + " has no whole-unit pixel grid at " +
                                    std::to_string(tile_px) + " px tiles");
  double xw, xe, yn, ys;
  box_units(box, xw, xe, yn, ys);
  const std::int64_t p = std::int64_t{1} << (32 - z - log2_tile);
  if (p > kMaxPixelUnits)
    throw invalid_argument("z", "zoom " + std::to_string(z) + " is too coarse for a canvas");
  const auto x0 = static_cast<std::int64_t>(std::floor(xw / p));
  const auto x1 = static_cast<std::int64_t>(std::ceil(xe / p));
  const auto y0 = static_cast<std::int64_t>(std::floor(yn / p));
  const auto y1 = static_cast<std::int64_t>(std::ceil(ys / p));
  const std::int64_t w = std::max<std::int64_t>(1, x1 - x0), h = std::max<std::int64_t>(1, y1 - y0);
  if (w + 2 * margin_px > kMaxCanvasPx)
    throw invalid_argument("width", "the box is " + std::to_string(w) + " px wide at zoom " +
                                        std::to_string(z) + " (max " + std::to_string(kMaxCanvasPx) + ")");
  if (h + 2 * margin_px > kMaxCanvasPx)
    throw invalid_argument("height", "the box is " + std::to_string(h) + " px high at zoom " +
                                         std::to_string(z) + " (max " + std::to_string(kMaxCanvasPx) + ")");
  return Canvas((x0 - margin_px) * p, (y0 - margin_px) * p, p, static_cast<int>(w) + 2 * margin_px,
                static_cast<int>(h) + 2 * margin_px, margin_px);
}

Canvas Canvas::inner() const {
  return Canvas(origin_x_ + margin_ * pixel_units_, origin_y_ + margin_ * pixel_units_, pixel_units_,
                inner_width(), inner_height(), 0);
}

Canvas Canvas::with_margin(int margin_px) const {
  if (margin_px < 0) throw invalid_argument("margin", "margin must not be negative");
  return Canvas(origin_x_ - margin_px * pixel_units_, origin_y_ - margin_px * pixel_units_, pixel_units_,
                width_ + 2 * margin_px, height_ + 2 * margin_px, margin_ + margin_px);
}

geo::LonLatBox Canvas::bounds() const {
  const double x0 = static_cast<double>(origin_x_ + margin_ * pixel_units_);
  const double y0 = static_cast<double>(origin_y_ + margin_ * pixel_units_);
  geo::LonLatBox b;
  b.west = geo::merc_x_to_lon(x0);
  b.east = geo::merc_x_to_lon(x0 + static_cast<double>(pixel_units_) * inner_width());
  b.north = geo::merc_y_to_lat(y0);
  b.south = geo::merc_y_to_lat(y0 + static_cast<double>(pixel_units_) * inner_height());
  return b;
}

std::string Canvas::describe() const {
  return "origin=(" + std::to_string(origin_x_) + "," + std::to_string(origin_y_) +
         ") px=" + std::to_string(pixel_units_) + " size=" + std::to_string(width_) + "x" +
         std::to_string(height_) + " margin=" + std::to_string(margin_);
}

}  // namespace trailscope::density
