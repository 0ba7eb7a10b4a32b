#include "trailscope/geo/web_mercator.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace trailscope::geo {
namespace {
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
constexpr double kWorld = 4294967296.0;  // 2^32

std::uint32_t to_u32(double units) noexcept {
  if (!(units > 0.0)) return 0;  // also NaN
  if (units >= kWorld - 1.0) return 0xFFFFFFFFu;
  return static_cast<std::uint32_t>(units);  // floor, units > 0
}
}  // namespace

double clamp_latitude(double lat_deg) noexcept {
  if (std::isnan(lat_deg)) return lat_deg;
  return std::clamp(lat_deg, -kMaxLatitude, kMaxLatitude);
}

double wrap_longitude(double lon_deg) noexcept {
  if (lon_deg >= -180.0 && lon_deg < 180.0) return lon_deg;  // the common case, bit-exact
  if (!std::isfinite(lon_deg)) return lon_deg;
  double w = std::fmod(lon_deg + 180.0, 360.0);
  if (w < 0) w += 360.0;
  w -= 180.0;
  return w >= 180.0 ? -180.0 : w;
}

double lon_to_unit_x(double lon_deg) noexcept {
  return (wrap_longitude(lon_deg) + 180.0) / 360.0;
}

double lat_to_unit_y(double lat_deg) noexcept {
  const double phi = clamp_latitude(lat_deg) * kDeg;
  const double y = 0.5 - std::asinh(std::tan(phi)) / (2.0 * kPi);
  return std::clamp(y, 0.0, 1.0);  // asinh(tan) at the clamp can round a hair past π
}

double unit_x_to_lon(double x) noexcept {
  return x * 360.0 - 180.0;
}

double unit_y_to_lat(double y) noexcept {
  return std::atan(std::sinh(kPi * (1.0 - 2.0 * y))) / kDeg;
}

std::uint32_t lon_to_merc_x(double lon_deg) noexcept {
  if (std::isnan(lon_deg)) return 0;
  return to_u32(lon_to_unit_x(lon_deg) * kWorld);
}

std::uint32_t lat_to_merc_y(double lat_deg) noexcept {
  if (std::isnan(lat_deg)) return 0;
  return to_u32(lat_to_unit_y(lat_deg) * kWorld);
}

double merc_x_to_lon(double x_units) noexcept {
  return unit_x_to_lon(x_units / kWorld);
}
double merc_y_to_lat(double y_units) noexcept {
  return unit_y_to_lat(y_units / kWorld);
}

double lon_to_meters_x(double lon_deg) noexcept {
  return kEarthRadiusMeters * lon_deg * kDeg;
}

double lat_to_meters_y(double lat_deg) noexcept {
  return kEarthRadiusMeters * std::asinh(std::tan(clamp_latitude(lat_deg) * kDeg));
}

}  // namespace trailscope::geo
