#include "formats/bundle_export.hpp"

#include <bit>
#include <cmath>
#include <cstring>
#include <numbers>

#include "trailscope/bundling/graph_io.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/geo/web_mercator.hpp"

namespace trailscope::server {

static_assert(std::endian::native == std::endian::little,
              "TSBL is written by copying host floats: a big-endian host would need byte swaps");

namespace {
constexpr double kWorldMeters = 2 * std::numbers::pi * geo::kEarthRadiusMeters;

/// Source units (after Frame::from_pixels) to the wire: lon/lat for geographic units.
void to_wire(BundleUnits u, double& x, double& y) {
  switch (u) {
    case BundleUnits::merc32:
      x = geo::merc_x_to_lon(x), y = geo::merc_y_to_lat(y);
      return;
    case BundleUnits::epsg3857:
      x = geo::unit_x_to_lon(0.5 + x / kWorldMeters), y = geo::unit_y_to_lat(0.5 - y / kWorldMeters);
      return;
    case BundleUnits::plane:
      return;
  }
}

/// Bundle pixels → wire coordinates, in place.
bundling::Polylines wire(const StoredBundle& b, const bundling::Polylines& px) {
  bundling::Polylines out = b.bundled.frame.from_pixels(px);
  for (std::size_t i = 0; i < out.points(); ++i) to_wire(b.units, out.x[i], out.y[i]);
  return out;
}

/// Wire units per bundle pixel along x: the unit of the relaxation cap's lengths in TSBL.
double wire_units_per_px(const StoredBundle& b) {
  const double src = 1.0 / b.bundled.frame.scale;
  switch (b.units) {
    case BundleUnits::merc32:
      return src * 360.0 / static_cast<double>(geo::kWorldUnits);
    case BundleUnits::epsg3857:
      return src * 360.0 / kWorldMeters;
    case BundleUnits::plane:
      return src;
  }
  return src;
}

bundling::Polylines relaxed(const StoredBundle& b, double relaxation) {
  return bundling::relax(b.bundled, effective_relaxation(b, relaxation), b.bundled.params.max_displacement);
}

template <typename T>
void put(std::string& out, T v) {
  char buf[sizeof(T)];
  std::memcpy(buf, &v, sizeof(T));
  out.append(buf, sizeof(T));
}

void put_xy(std::string& out, const bundling::Polylines& p) {
  for (std::size_t i = 0; i < p.points(); ++i) {
    put(out, static_cast<float>(p.x[i]));
    put(out, static_cast<float>(p.y[i]));
  }
}
}  // namespace

bool wire_lonlat(BundleUnits u) noexcept {
  return u != BundleUnits::plane;
}

double effective_relaxation(const StoredBundle& b, double requested) noexcept {
  return requested >= 0 ? requested : b.bundled.params.relaxation;
}

nlohmann::json polylines_json(const StoredBundle& b, double relaxation, std::size_t max_points) {
  const std::size_t points = b.bundled.lines.points();
  if (points > max_points)
    throw Error(Error::Kind::payload_too_large, "format",
                "bundle '" + b.id + "' has " + std::to_string(points) + " points; JSON is limited to " +
                    std::to_string(max_points) + " points per response: use format=binary");
  const bundling::Polylines p = wire(b, relaxed(b, relaxation));
  nlohmann::json lines = nlohmann::json::array();
  for (std::size_t i = 0; i < p.size(); ++i) {
    nlohmann::json line = nlohmann::json::array();
    for (std::size_t k = p.begin(i); k < p.end(i); ++k) line.push_back({p.x[k], p.y[k]});
    lines.push_back(std::move(line));
  }
  return {{"bundle", b.id},
          {"coordinates", wire_lonlat(b.units) ? "lonlat" : "source"},
          {"relaxation", effective_relaxation(b, relaxation)},
          {"polylines", std::move(lines)}};
}

std::string polylines_binary(const StoredBundle& b, double relaxation) {
  const bundling::Polylines bundled = wire(b, relaxed(b, relaxation));
  const bundling::Polylines original = wire(b, b.bundled.original);
  const std::size_t n = bundled.size(), m = bundled.points();
  std::string out;
  out.reserve(32 + 4 * (n + 1) + 16 * m + 4 * n);
  out.append(kPolylinesMagic, 4);
  put<std::uint32_t>(out, kPolylinesVersion);
  put<std::uint32_t>(out, wire_lonlat(b.units) ? 1u : 0u);
  put<std::uint32_t>(out, static_cast<std::uint32_t>(n));
  put<std::uint32_t>(out, static_cast<std::uint32_t>(m));
  put<float>(out, static_cast<float>(effective_relaxation(b, relaxation)));
  put<float>(out, static_cast<float>(b.bundled.params.max_displacement));
  put<std::uint32_t>(out, 0);
  for (std::uint32_t o : bundled.offsets) put(out, o);
  put_xy(out, bundled);
  put_xy(out, original);
  const double k = wire_units_per_px(b);
  for (float len : b.bundled.length) put(out, static_cast<float>(len * k));
  return out;
}

std::string polylines_trl(const StoredBundle& b, double relaxation) {
  return bundling::write_trl(wire(b, relaxed(b, relaxation)));
}

}  // namespace trailscope::server
