// Sector fields of traffic and uploaded vector fields (field.hpp).
#include "trailscope/flow/field.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "bundling/render/render_detail.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/geo/web_mercator.hpp"
#include "trailscope/trails/point_filter.hpp"

namespace trailscope::flow {
namespace {

constexpr double kWorld = static_cast<double>(geo::kWorldUnits);
constexpr double kPi = 3.14159265358979323846;
/// Fixed point of the accumulation: integer sums are associative, so threads cannot change the bits.
constexpr double kFix = 1048576.0;  // 2^20

struct Accum {
  std::vector<std::int64_t> v;  // per sector: 3 · cells (sx, sy, w interleaved)
};

/// Adds the straight segment (ax, ay) → (bx, by) (cell coordinates) to `acc`, cut at the cell edges.
void deposit(double ax, double ay, double bx, double by, int sector, const Grid& g, std::int64_t* acc) {
  const double dx = bx - ax, dy = by - ay;
  const double len = std::hypot(dx, dy);
  if (!(len > 0)) return;
  // Clipped to [0, nx] × [0, ny] (Liang–Barsky, as the bundle renderer clips its segments).
  double t0 = 0, t1 = 1;
  if (!bundling::detail::clip_parameters(ax, ay, dx, dy, 0, 0, g.nx, g.ny, t0, t1) || !(t1 > t0)) return;
  // Every crossing of an integer x or y line between t0 and t1.
  thread_local std::vector<double> ts;  // no allocation per segment
  ts.clear();
  ts.push_back(t0);
  const auto crossings = [&](double a, double d) {
    if (d == 0) return;
    const double p0 = a + t0 * d, p1 = a + t1 * d;
    const double lo = std::min(p0, p1), hi = std::max(p0, p1);
    for (double k = std::floor(lo) + 1; k < hi; k += 1) ts.push_back((k - a) / d);
  };
  crossings(ax, dx);
  crossings(ay, dy);
  ts.push_back(t1);
  std::sort(ts.begin(), ts.end());
  const double ux = dx / len, uy = dy / len;
  for (std::size_t k = 0; k + 1 < ts.size(); ++k) {
    const double piece = (ts[k + 1] - ts[k]) * len;
    if (!(piece > 0)) continue;
    const double tm = 0.5 * (ts[k] + ts[k + 1]);
    const int i = std::clamp(static_cast<int>(std::floor(ax + tm * dx)), 0, g.nx - 1);
    const int j = std::clamp(static_cast<int>(std::floor(ay + tm * dy)), 0, g.ny - 1);
    std::int64_t* c = acc + (static_cast<std::size_t>(sector) * g.cells() + g.index(i, j)) * 3;
    c[0] += std::llround(piece * ux * kFix);
    c[1] += std::llround(piece * uy * kFix);
    c[2] += std::llround(piece * kFix);
  }
}

/// One pass of the separable [1 2 1]/4 filter, zero outside the grid.
void smooth_once(std::vector<float>& v, int nx, int ny) {
  std::vector<float> tmp(v.size());
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const std::size_t c = static_cast<std::size_t>(j) * nx + i;
      const float l = i > 0 ? v[c - 1] : 0.f, r = i + 1 < nx ? v[c + 1] : 0.f;
      tmp[c] = 0.25f * l + 0.5f * v[c] + 0.25f * r;
    }
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const std::size_t c = static_cast<std::size_t>(j) * nx + i;
      const float u = j > 0 ? tmp[c - nx] : 0.f, d = j + 1 < ny ? tmp[c + nx] : 0.f;
      v[c] = 0.25f * u + 0.5f * tmp[c] + 0.25f * d;
    }
}

}  // namespace

double Grid::lon(double x) const {
  return geo::merc_x_to_lon(std::fmod(x0 + x * cell + 4 * kWorld, kWorld));
}
double Grid::lat(double y) const {
  return geo::merc_y_to_lat(y0 + y * cell);
}

double VectorField::sector_heading(int k) const {
  if (!by_heading) return std::numeric_limits<double>::quiet_NaN();
  return 360.0 * k / static_cast<double>(sectors.size());
}

void FieldParams::validate() const {
  if (grid < 8 || grid > limits::kMaxFlowGridCells)
    throw invalid_argument("grid", "grid must be 8.." + std::to_string(limits::kMaxFlowGridCells) +
                                       " cells (limits::kMaxFlowGridCells)");
  if (sectors < 1 || sectors > limits::kMaxFlowSectors)
    throw invalid_argument("sectors", "sectors must be 1.." + std::to_string(limits::kMaxFlowSectors) +
                                          " (limits::kMaxFlowSectors)");
  if (smooth < 0 || smooth > 8) throw invalid_argument("smooth", "smooth must be 0..8 passes");
  if (!(max_gap_seconds > 0)) throw invalid_argument("max_gap", "max_gap must be > 0 seconds");
}

int sector_of(double heading_deg, int sectors) {
  double h = std::fmod(heading_deg, 360.0);
  if (h < 0) h += 360.0;
  const int k = static_cast<int>(std::floor(h * sectors / 360.0 + 0.5));
  return k % sectors;
}

Grid traffic_grid(const TrailSet& trails, const Query& query, int cells) {
  double west, south, east, north;
  if (query.bbox) {
    west = query.bbox->west, south = query.bbox->south, east = query.bbox->east, north = query.bbox->north;
  } else {
    west = 180, south = 90, east = -180, north = -90;
    bool any = false, wraps = false;
    for (const Flight& f : trails.flights()) {
      if (!query.may_match(f)) continue;
      any = true;
      wraps = wraps || f.crosses_antimeridian;
      west = std::min<double>(west, f.lon_min), east = std::max<double>(east, f.lon_max);
      south = std::min<double>(south, f.lat_min), north = std::max<double>(north, f.lat_max);
    }
    if (!any) throw Error(Error::Kind::unprocessable, "query", "no flight matches the query");
    if (wraps) west = -180, east = 180;
  }
  const double x0 = geo::lon_to_unit_x(west) * kWorld;
  double x1 = geo::lon_to_unit_x(east) * kWorld;
  if (west > east) x1 += kWorld;
  const double y0 = geo::lat_to_unit_y(north) * kWorld, y1 = geo::lat_to_unit_y(south) * kWorld;
  Grid g;
  g.geographic = true;
  const double span = std::max({x1 - x0, y1 - y0, 1.0});
  g.cell = std::max(1.0, std::ceil(span / cells));
  g.x0 = std::floor(x0), g.y0 = std::floor(y0);
  g.nx = std::clamp(static_cast<int>(std::ceil((x1 - g.x0) / g.cell)), 1, cells);
  g.ny = std::clamp(static_cast<int>(std::ceil((y1 - g.y0) / g.cell)), 1, cells);
  return g;
}

VectorField traffic_field(const TrailSet& trails, const Query& query, const FieldParams& params) {
  params.validate();
  VectorField out;
  out.grid = traffic_grid(trails, query, params.grid);
  const Grid& g = out.grid;
  const int S = params.sectors;
  const PointFilter filter(query);
  const PointColumns& pts = trails.points();
  const auto& mx = trails.merc_x();
  const auto& my = trails.merc_y();
  const std::size_t n = static_cast<std::size_t>(S) * g.cells() * 3;
  tbb::enumerable_thread_specific<Accum> local([n] { return Accum{std::vector<std::int64_t>(n, 0)}; });
  const auto& flights = trails.flights();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, flights.size(), 64), [&](const auto& r) {
    std::int64_t* acc = local.local().v.data();
    for (std::size_t fi = r.begin(); fi < r.end(); ++fi) {
      const Flight& f = flights[fi];
      if (!query.may_match(f)) continue;
      const bool all = filter.contains(f);
      bool have = false;
      double px = 0, py = 0, pt = 0;
      for (std::size_t i = f.begin; i < f.end; ++i) {
        if (!all && !filter(pts, i)) {
          have = false;
          continue;
        }
        double x = mx[i];
        if (have) x += std::round((px - x) / kWorld) * kWorld;  // the short way across 180°
        const double y = my[i], t = pts.t[i];
        if (have && t - pt <= params.max_gap_seconds) {
          const double dx = x - px, dy = y - py;
          if (dx != 0 || dy != 0) {
            const double heading = std::atan2(dx, -dy) * 180.0 / kPi;  // compass: y grows southward
            const int s = sector_of(heading, S);
            deposit((px - g.x0) / g.cell, (py - g.y0) / g.cell, (x - g.x0) / g.cell, (y - g.y0) / g.cell, s,
                    g, acc);
          }
        }
        px = x, py = y, pt = t, have = true;
      }
    }
  });
  std::vector<std::int64_t> sum(n, 0);
  for (const Accum& a : local)
    for (std::size_t k = 0; k < n; ++k) sum[k] += a.v[k];
  out.sectors.resize(S);
  for (int s = 0; s < S; ++s) {
    SectorField& f = out.sectors[s];
    f.sx.resize(g.cells()), f.sy.resize(g.cells()), f.w.resize(g.cells());
    const std::int64_t* base = sum.data() + static_cast<std::size_t>(s) * g.cells() * 3;
    for (std::size_t c = 0; c < g.cells(); ++c) {
      f.sx[c] = static_cast<float>(base[3 * c] / kFix);
      f.sy[c] = static_cast<float>(base[3 * c + 1] / kFix);
      f.w[c] = static_cast<float>(base[3 * c + 2] / kFix);
    }
    for (int k = 0; k < params.smooth; ++k)
      smooth_once(f.sx, g.nx, g.ny), smooth_once(f.sy, g.nx, g.ny), smooth_once(f.w, g.nx, g.ny);
  }
  return out;
}

VectorField parse_field(const std::string& text) {
  if (text.size() > limits::kMaxFlowFieldBytes)
    throw Error(Error::Kind::payload_too_large, "field",
                "a vector field file may have at most " + std::to_string(limits::kMaxFlowFieldBytes) +
                    " bytes (limits::kMaxFlowFieldBytes)");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw Error(Error::Kind::unsupported_format, "field", std::string("not JSON: ") + e.what());
  }
  if (!j.is_object())
    throw Error(Error::Kind::unsupported_format, "field",
                "a vector field is a JSON object (proto/flow_field.md)");
  if (!j.contains("format") || j["format"] != "trailscope-flow-field")
    throw invalid_argument("format", "format must be \"trailscope-flow-field\"");
  if (!j.contains("version") || j["version"] != 1) throw invalid_argument("version", "version must be 1");
  const auto dim = [&](const char* name) {
    if (!j.contains(name) || !j[name].is_number_integer())
      throw invalid_argument(name, std::string(name) + " must be an integer number of cells");
    const auto v = j[name].get<std::int64_t>();
    if (v < 2 || v > limits::kMaxFlowGridCells)
      throw invalid_argument(name, std::string(name) + " must be 2.." +
                                       std::to_string(limits::kMaxFlowGridCells) +
                                       " cells (limits::kMaxFlowGridCells)");
    return static_cast<int>(v);
  };
  VectorField out;
  out.by_heading = false;
  Grid& g = out.grid;
  g.nx = dim("width"), g.ny = dim("height");
  const auto array = [&](const char* name, bool required) {
    std::vector<float> v;
    if (!j.contains(name)) {
      if (required) throw invalid_argument(name, std::string(name) + " is missing");
      return v;
    }
    const auto& a = j[name];
    if (!a.is_array() || a.size() != g.cells())
      throw invalid_argument(name, std::string(name) + " must be an array of width × height = " +
                                       std::to_string(g.cells()) + " numbers (row 0 at the top)");
    v.resize(g.cells());
    for (std::size_t k = 0; k < g.cells(); ++k) {
      if (a[k].is_null()) {
        v[k] = std::numeric_limits<float>::quiet_NaN();
      } else if (a[k].is_number()) {
        const double d = a[k].get<double>();
        if (!std::isfinite(d) || std::abs(d) > 1e30)
          throw invalid_argument(name,
                                 std::string(name) + "[" + std::to_string(k) + "] is not a finite number");
        v[k] = static_cast<float>(d);
      } else {
        throw invalid_argument(name,
                               std::string(name) + "[" + std::to_string(k) + "] must be a number or null");
      }
    }
    return v;
  };
  const std::vector<float> u = array("u", true), v = array("v", true), wt = array("weight", false);
  if (j.contains("bbox")) {
    const auto& b = j["bbox"];
    if (!b.is_array() || b.size() != 4 ||
        !std::all_of(b.begin(), b.end(), [](const auto& x) { return x.is_number(); }))
      throw invalid_argument("bbox", "bbox must be [west, south, east, north] in degrees");
    const double w = b[0], s = b[1], e = b[2], n = b[3];
    if (!(w >= -180 && w <= 180 && e >= -180 && e <= 180 && s >= -85.0511 && n <= 85.0511 && s < n && w != e))
      throw invalid_argument("bbox",
                             "bbox must be [west, south, east, north] in degrees, south < north, "
                             "latitudes within ±85.0511 (west > east crosses 180°)");
    const double x0 = geo::lon_to_unit_x(w) * kWorld;
    double x1 = geo::lon_to_unit_x(e) * kWorld;
    if (w > e) x1 += kWorld;
    const double y0 = geo::lat_to_unit_y(n) * kWorld, y1 = geo::lat_to_unit_y(s) * kWorld;
    // Square cells: the grid is taken to span the box in x; its height follows from the cell.
    g.geographic = true;
    g.x0 = x0, g.y0 = y0;
    g.cell = (x1 - x0) / g.nx;
    if (std::abs((y1 - y0) / g.cell - g.ny) > 0.5 * g.ny)
      throw invalid_argument("bbox",
                             "bbox's Web Mercator aspect does not match width × height of square cells");
  }
  SectorField f;
  f.sx.assign(g.cells(), 0.f), f.sy.assign(g.cells(), 0.f), f.w.assign(g.cells(), 0.f);
  for (std::size_t k = 0; k < g.cells(); ++k) {
    const double ux = u[k], uy = -static_cast<double>(v[k]);  // v points north, cell y south
    const double m = std::hypot(ux, uy);
    if (!(m > 0) || std::isnan(m)) continue;
    double w = wt.empty() ? m : wt[k];
    if (std::isnan(w)) continue;
    if (w < 0) throw invalid_argument("weight", "weight[" + std::to_string(k) + "] must be >= 0");
    f.sx[k] = static_cast<float>(w * ux / m), f.sy[k] = static_cast<float>(w * uy / m);
    f.w[k] = static_cast<float>(w);
  }
  out.sectors.push_back(std::move(f));
  return out;
}

std::vector<float> total_traffic(const VectorField& field) {
  std::vector<float> t(field.grid.cells(), 0.f);
  for (const SectorField& s : field.sectors)
    for (std::size_t c = 0; c < t.size(); ++c) t[c] += s.w[c];
  return t;
}

}  // namespace trailscope::flow
