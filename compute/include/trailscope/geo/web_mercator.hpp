#pragma once
// Spherical Web Mercator (EPSG:3857), the projection of every slippy-map tile, in three forms:
//  - unit coordinates: x in [0, 1) west to east from 180°W, y in [0, 1] north to south (y = 0 is the
//    north edge at +kMaxLatitude), the form the tile maths works in;
//  - unsigned 32-bit fixed point over the whole world, x = 2^32·(lon+180)/360, as adsb.exposed stores it
//    (`mercator_x/y UInt32`): 2^32 units around the world is ~9.3 mm at the equator, enough for
//    pixel-exact tiles up to zoom 24 at 256 px;
//  - EPSG:3857 metres (x east, y north, origin at (0°, 0°)), for interoperability only.
// Latitudes are clamped to ±kMaxLatitude, where the square world ends; longitudes are wrapped into
// [-180, 180). The formulas are the usual ones (Snyder, "Map Projections: A Working Manual", USGS PP 1395,
// 1987, §7, on a sphere); y = ½ − asinh(tan φ)/2π is the same as ½ − ln tan(π/4 + φ/2)/2π.
#include <cstdint>

namespace trailscope::geo {

/// Latitude (degrees) of the north edge of the square Web Mercator world, atan(sinh(π)).
inline constexpr double kMaxLatitude = 85.051128779806592;
/// Radius (metres) of the sphere EPSG:3857 uses (the WGS84 semi-major axis).
inline constexpr double kEarthRadiusMeters = 6378137.0;
/// Fixed-point units around the world (2^32).
inline constexpr std::int64_t kWorldUnits = std::int64_t{1} << 32;

/// Clamps a latitude (degrees) to [-kMaxLatitude, kMaxLatitude]. NaN stays NaN.
double clamp_latitude(double lat_deg) noexcept;
/// Wraps a longitude (degrees, any finite value) into [-180, 180); 180 becomes -180. NaN stays NaN.
double wrap_longitude(double lon_deg) noexcept;

/// Longitude (degrees, wrapped first) to unit x in [0, 1).
double lon_to_unit_x(double lon_deg) noexcept;
/// Latitude (degrees, clamped first) to unit y in [0, 1], 0 at the north edge.
double lat_to_unit_y(double lat_deg) noexcept;
/// Unit x (any value; 1 is 180°E) to longitude (degrees), without wrapping: x = 1.25 gives 270.
double unit_x_to_lon(double x) noexcept;
/// Unit y (any value; values outside [0, 1] give latitudes beyond ±kMaxLatitude) to latitude (degrees).
double unit_y_to_lat(double y) noexcept;

/// Longitude (degrees) to 32-bit fixed-point x: floor(2^32·(lon+180)/360) after wrapping, in
/// [0, 2^32 − 1]. NaN gives 0 (callers reject NaN positions before this).
std::uint32_t lon_to_merc_x(double lon_deg) noexcept;
/// Latitude (degrees) to 32-bit fixed-point y: floor(2^32·lat_to_unit_y(lat)), clamped to
/// [0, 2^32 − 1] (the south edge −kMaxLatitude maps to 2^32 − 1). NaN gives 0.
std::uint32_t lat_to_merc_y(double lat_deg) noexcept;
/// Fixed-point x (any value, as double: sub-unit and out-of-world positions allowed) to longitude.
double merc_x_to_lon(double x_units) noexcept;
/// Fixed-point y (any value, as double) to latitude.
double merc_y_to_lat(double y_units) noexcept;

/// EPSG:3857 metres of a longitude/latitude (degrees; latitude clamped, longitude not wrapped).
double lon_to_meters_x(double lon_deg) noexcept;
double lat_to_meters_y(double lat_deg) noexcept;

}  // namespace trailscope::geo
