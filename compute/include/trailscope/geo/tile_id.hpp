#pragma once
// XYZ ("slippy map") tiles over Web Mercator, as OpenStreetMap, Leaflet, MapLibre, Datashader and
// adsb.exposed use them: at zoom z the square world is split into 2^z × 2^z tiles, x grows eastwards
// from 180°W, y grows southwards from the north edge (+85.0511°); y = 0 is the NORTH row (TMS flips it:
// y_tms = 2^z − 1 − y). A tile spans 2^(32−z) units of the 32-bit fixed-point Mercator
// (geo/web_mercator.hpp), so tile edges are exact integers up to zoom 32.
#include <array>
#include <cstdint>
#include <string>

namespace trailscope::geo {

/// A longitude/latitude box in degrees. west > east means the box crosses the 180° meridian.
struct LonLatBox {
  double west = -180, south = -90, east = 180, north = 90;
};

struct TileId {
  int z = 0;  ///< zoom, limits::kMinZoom..limits::kMaxZoom for served tiles
  int x = 0;  ///< column, 0..2^z − 1, west to east
  int y = 0;  ///< row, 0..2^z − 1, north to south
  bool operator==(const TileId&) const = default;
};

/// "z/x/y", e.g. "10/525/336".
std::string to_string(const TileId& t);

/// Throws invalid_argument naming `z` when z is outside limits::kMinZoom..kMaxZoom, else `x` or `y`
/// when that index is outside 0..2^z − 1.
void validate_tile(const TileId& t);

/// The tile at zoom z that holds (lon, lat) in degrees: lon is wrapped into [-180, 180), lat clamped to
/// ±kMaxLatitude; points on a tile edge belong to the tile east / south of it (the south edge of the
/// world belongs to the last row). Throws invalid_argument(`z`) as validate_tile does.
TileId tile_for_lonlat(double lon_deg, double lat_deg, int z);

/// Longitude/latitude bounds of a tile (degrees; west < east, north = kMaxLatitude for y = 0).
/// Validates the tile first.
LonLatBox tile_bounds(const TileId& t);

/// The tile one zoom up that contains t (t.z must be > 0; throws invalid_argument(`z`) otherwise).
TileId parent(const TileId& t);
/// The four tiles one zoom down, in the order NW, NE, SW, SE. Throws invalid_argument(`z`) at kMaxZoom.
std::array<TileId, 4> children(const TileId& t);

/// Edge length of any tile at zoom z in 32-bit Mercator units (2^(32−z)); z in 0..32.
constexpr std::int64_t tile_size_units(int z) {
  return std::int64_t{1} << (32 - z);
}
/// North-west corner of a tile in 32-bit Mercator units (x, y), exact.
constexpr std::int64_t tile_origin_x(const TileId& t) {
  return std::int64_t{t.x} * tile_size_units(t.z);
}
constexpr std::int64_t tile_origin_y(const TileId& t) {
  return std::int64_t{t.y} * tile_size_units(t.z);
}

}  // namespace trailscope::geo
