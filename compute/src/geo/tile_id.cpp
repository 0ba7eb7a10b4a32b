#include "trailscope/geo/tile_id.hpp"

#include <cmath>

#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/geo/web_mercator.hpp"

namespace trailscope::geo {
namespace {
void validate_zoom(int z) {
  if (z < limits::kMinZoom || z > limits::kMaxZoom)
    throw invalid_argument("z", "zoom " + std::to_string(z) + " is outside " +
                                    std::to_string(limits::kMinZoom) + ".." +
                                    std::to_string(limits::kMaxZoom));
}

int unit_to_index(double unit, int z) {
  const std::int64_t n = std::int64_t{1} << z;
  const auto i = static_cast<std::int64_t>(std::floor(unit * static_cast<double>(n)));
  return static_cast<int>(i < 0 ? 0 : (i >= n ? n - 1 : i));
}
}  // namespace

std::string to_string(const TileId& t) {
  return std::to_string(t.z) + "/" + std::to_string(t.x) + "/" + std::to_string(t.y);
}

void validate_tile(const TileId& t) {
  validate_zoom(t.z);
  const std::int64_t n = std::int64_t{1} << t.z;
  const std::string range = " is outside 0.." + std::to_string(n - 1) + " at zoom " + std::to_string(t.z);
  if (t.x < 0 || t.x >= n) throw invalid_argument("x", "tile column " + std::to_string(t.x) + range);
  if (t.y < 0 || t.y >= n) throw invalid_argument("y", "tile row " + std::to_string(t.y) + range);
}

TileId tile_for_lonlat(double lon_deg, double lat_deg, int z) {
  validate_zoom(z);
  return TileId{z, unit_to_index(lon_to_unit_x(lon_deg), z), unit_to_index(lat_to_unit_y(lat_deg), z)};
}

LonLatBox tile_bounds(const TileId& t) {
  validate_tile(t);
  const double n = std::ldexp(1.0, t.z);
  LonLatBox b;
  b.west = unit_x_to_lon(t.x / n);
  b.east = unit_x_to_lon((t.x + 1) / n);
  b.north = unit_y_to_lat(t.y / n);
  b.south = unit_y_to_lat((t.y + 1) / n);
  return b;
}

TileId parent(const TileId& t) {
  validate_tile(t);
  if (t.z == 0) throw invalid_argument("z", "tile 0/0/0 has no parent");
  return TileId{t.z - 1, t.x / 2, t.y / 2};
}

std::array<TileId, 4> children(const TileId& t) {
  validate_tile(t);
  if (t.z >= limits::kMaxZoom)
    throw invalid_argument(
        "z", "tiles at zoom " + std::to_string(t.z) + " have no children within the zoom limit");
  const int z = t.z + 1, x = 2 * t.x, y = 2 * t.y;
  return {TileId{z, x, y}, TileId{z, x + 1, y}, TileId{z, x, y + 1}, TileId{z, x + 1, y + 1}};
}

}  // namespace trailscope::geo
