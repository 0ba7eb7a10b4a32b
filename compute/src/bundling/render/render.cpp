// render_bundle (render.hpp): parameters, viewports, the pipeline, and XYZ tiles. The stages are in
// render_density.cpp (density, local maximum, lighting), render_lines.cpp (colours, lines, compositing)
// and render_math.cpp (the formulas).
#include "trailscope/bundling/render.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numeric>

#include "bundling/render/render_detail.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/text.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/density/colormap.hpp"
#include "trailscope/geo/tile_id.hpp"

namespace trailscope::bundling {
namespace {

void check_range(const char* name, double v, double lo, double hi) {
  if (!(v >= lo && v <= hi))
    throw invalid_argument(name, std::string(name) + " " + format_double(v) + " is outside " +
                                     format_double(lo) + ".." + format_double(hi));
}

double parse_number(std::string_view value, const std::string& name) {
  double v = 0;
  std::string_view s = value;
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v))
    throw invalid_argument(name, name + " '" + std::string(value) + "' is not a number");
  return v;
}

int parse_int(std::string_view value, const std::string& name) {
  const double v = parse_number(value, name);
  if (v != std::floor(v) || std::fabs(v) > 1e9)
    throw invalid_argument(name, name + " '" + std::string(value) + "' is not an integer");
  return static_cast<int>(v);
}

bool parse_bool(std::string_view value, const std::string& name) {
  if (value == "true" || value == "1") return true;
  if (value == "false" || value == "0") return false;
  throw invalid_argument(name, name + " '" + std::string(value) + "' is not true or false");
}

}  // namespace

Style parse_style(std::string_view t, const std::string& param) {
  if (t == "lines") return Style::lines;
  if (t == "shaded") return Style::shaded;
  if (t == "tube") return Style::tube;
  throw invalid_argument(param, param + " '" + std::string(t) + "' is not one of lines, shaded, tube");
}
ColorBy parse_color_by(std::string_view t, const std::string& param) {
  if (t == "length") return ColorBy::length;
  if (t == "direction") return ColorBy::direction;
  if (t == "density") return ColorBy::density;
  if (t == "displacement") return ColorBy::displacement;
  if (t == "flat") return ColorBy::flat;
  throw invalid_argument(param, param + " '" + std::string(t) +
                                    "' is not one of length, direction, density, displacement, flat");
}
AlphaMode parse_alpha_mode(std::string_view t, const std::string& param) {
  if (t == "constant") return AlphaMode::constant;
  if (t == "value") return AlphaMode::value;
  if (t == "inverse") return AlphaMode::inverse;
  throw invalid_argument(param, param + " '" + std::string(t) + "' is not one of constant, value, inverse");
}
const char* to_string(Style s) noexcept {
  return s == Style::lines ? "lines" : s == Style::shaded ? "shaded" : "tube";
}
const char* to_string(ColorBy c) noexcept {
  switch (c) {
    case ColorBy::length:
      return "length";
    case ColorBy::direction:
      return "direction";
    case ColorBy::density:
      return "density";
    case ColorBy::displacement:
      return "displacement";
    case ColorBy::flat:
      return "flat";
  }
  return "?";
}
const char* to_string(AlphaMode a) noexcept {
  return a == AlphaMode::constant ? "constant" : a == AlphaMode::value ? "value" : "inverse";
}

void RenderParams::validate() const {
  check_range("width", width, 16, limits::kMaxBundleImagePx);
  if (height != 0) check_range("height", height, 16, limits::kMaxBundleImagePx);
  check_range("alpha", alpha, 0, 1);
  check_range("shading_radius", shading_radius, 0, 32);
  check_range("local_max_radius", local_max_radius, 1, 256);
  check_range("line_width", line_width, 0.5, 8);
  density::colormap(cmap, "cmap");
  if (background != "black" && background != "white" && background != "transparent")
    throw invalid_argument("background",
                           "background '" + background + "' is not one of black, white, transparent");
  if (std::isnan(relaxation) || relaxation > 1)
    throw invalid_argument(
        "relaxation", "relaxation " + format_double(relaxation) + " is outside 0..1 (or < 0: the bundle's)");
}

void RenderParams::set(std::string_view name, std::string_view value) {
  // Set on a copy and validate it, so a refused value leaves *this as it was.
  RenderParams next = *this;
  next.assign(name, value);
  next.validate();
  *this = std::move(next);
}

void RenderParams::assign(std::string_view name, std::string_view value) {
  const std::string n(name);
  if (n == "width") {
    width = parse_int(value, n);
  } else if (n == "height") {
    height = parse_int(value, n);
  } else if (n == "style") {
    style = parse_style(value, n);
  } else if (n == "color") {
    color = parse_color_by(value, n);
  } else if (n == "alpha_mode") {
    alpha_mode = parse_alpha_mode(value, n);
  } else if (n == "alpha") {
    alpha = parse_number(value, n);
  } else if (n == "alpha_by_density") {
    alpha_by_density = parse_bool(value, n);
  } else if (n == "shading_radius") {
    shading_radius = parse_number(value, n);
  } else if (n == "local_max_radius") {
    local_max_radius = parse_number(value, n);
  } else if (n == "line_width") {
    line_width = parse_number(value, n);
  } else if (n == "cmap") {
    cmap = std::string(value);
  } else if (n == "background") {
    background = std::string(value);
  } else if (n == "relaxation") {
    relaxation = parse_number(value, n);
  } else {
    throw invalid_argument(n, "unknown render parameter '" + n + "'");
  }
}

Viewport Viewport::whole(const Bundled& b, const RenderParams& params) {
  params.validate();
  const Frame& f = b.frame;
  const double size = f.size;
  double ax = 0, ay = 0, aw = size, ah = size;  // the area shown, bundle px
  // A view frame fills one axis exactly (offset 0 up to rounding); a fitted one has a border on both.
  if (std::min(f.offset_x, f.offset_y) < 1e-6 * size) {
    ax = std::max(0.0, f.offset_x), ay = std::max(0.0, f.offset_y);
    aw = size - 2 * ax, ah = size - 2 * ay;
  }
  Viewport v;
  v.width = params.width;
  v.scale = params.width / aw;
  v.height = params.height > 0 ? params.height : std::max(1, static_cast<int>(std::lround(ah * v.scale)));
  v.x0 = ax;
  v.y0 = ay + ah / 2 - v.height / (2 * v.scale);
  return v;
}

namespace {

void check_bundle(const Bundled& b) {
  const std::size_t n = b.lines.size(), p = b.lines.points();
  if (b.original.offsets != b.lines.offsets || b.t.size() != p || b.length.size() != n || b.angle.size() != n)
    throw Error(Error::Kind::unprocessable, "bundle",
                "the bundle's original points, t, length and angle do not match its " + std::to_string(n) +
                    " polylines of " + std::to_string(p) + " points");
}

detail::ViewLines view_lines(const Bundled& b, const RenderParams& params, const Viewport& v) {
  const double relaxation = params.relaxation < 0 ? b.params.relaxation : params.relaxation;
  const double md = b.params.max_displacement;
  const Polylines relaxed = relax(b, relaxation, md);
  detail::ViewLines out;
  const std::size_t n = relaxed.size();
  out.px.offsets = relaxed.offsets;
  out.px.x.resize(relaxed.points());
  out.px.y.resize(relaxed.points());
  out.displacement.resize(relaxed.points());
  for (std::size_t i = 0; i < n; ++i) {
    const double cap = md * b.length[i];
    for (std::size_t k = relaxed.begin(i); k < relaxed.end(i); ++k) {
      out.px.x[k] = (relaxed.x[k] - v.x0) * v.scale;
      out.px.y[k] = (relaxed.y[k] - v.y0) * v.scale;
      const double d = std::hypot(relaxed.x[k] - b.original.x[k], relaxed.y[k] - b.original.y[k]);
      out.displacement[k] = cap > 0 ? static_cast<float>(std::min(1.0, d / cap)) : 0.0f;
    }
  }
  out.order.resize(n);
  std::iota(out.order.begin(), out.order.end(), 0u);
  std::stable_sort(out.order.begin(), out.order.end(),
                   [&](std::uint32_t a, std::uint32_t c) { return b.length[a] < b.length[c]; });
  out.len.resize(n);
  if (n == 0) return out;  // nothing to draw: an empty image of the background
  const auto [lo, hi] = std::minmax_element(b.length.begin(), b.length.end());
  for (std::size_t i = 0; i < n; ++i) out.len[i] = *hi > *lo ? (b.length[i] - *lo) / (*hi - *lo) : 1.0f;
  return out;
}

}  // namespace

density::Image render_bundle(const Bundled& bundled, const RenderParams& params) {
  return render_bundle(bundled, params, Viewport::whole(bundled, params));
}

density::Image render_bundle(const Bundled& bundled, const RenderParams& params, const Viewport& view) {
  params.validate();
  check_range("width", view.width, 1, limits::kMaxBundleImagePx);
  check_range("height", view.height, 1, limits::kMaxBundleImagePx);
  if (!(view.scale > 0 && std::isfinite(view.scale) && std::isfinite(view.x0) && std::isfinite(view.y0)))
    throw invalid_argument("scale", "the viewport needs a finite origin and a scale > 0");
  check_bundle(bundled);
  const detail::ViewLines lines = view_lines(bundled, params, view);
  // The plain lines style needs the density only for the density colour or alpha.
  const bool need_density =
      params.style != Style::lines || params.color == ColorBy::density || params.alpha_by_density;
  detail::DensityMaps maps;
  if (need_density)
    maps = detail::density_maps(lines.px, view.width, view.height, params, params.style == Style::shaded);
  return detail::composite(bundled, lines, maps, params, view.width, view.height);
}

int tile_margin_px(const RenderParams& params) {
  // Smoothing reaches shading_radius, the local maximum floor(local_max_radius) further, the gradient
  // one more pixel, a line's coverage line_width/2 + 0.5; plus one pixel of slack.
  return static_cast<int>(std::ceil(params.shading_radius) + std::floor(params.local_max_radius) +
                          std::ceil(params.line_width / 2 + 0.5)) +
         2;
}

Viewport tile_viewport(const Bundled& b, int z, int x, int y, int tile_size, int tiles_x, int tiles_y,
                       int margin_px) {
  geo::validate_tile(geo::TileId{z, x, y});
  if (tile_size < 16 || tile_size > 4096)
    throw invalid_argument("tile_size", "tile_size " + std::to_string(tile_size) + " is outside 16..4096");
  if (b.frame.flip_y)
    throw Error(Error::Kind::unprocessable, "frame",
                "bundle tiles need a frame in Web Mercator units without flip_y (y already points south)");
  // Zoom-z pixels per Mercator unit, and per bundle pixel.
  const double px_per_unit = std::ldexp(static_cast<double>(tile_size), z - 32);
  Viewport v;
  v.scale = px_per_unit / b.frame.scale;
  v.x0 = b.frame.to_px_x(static_cast<double>(geo::tile_origin_x(geo::TileId{z, x, y}))) - margin_px / v.scale;
  v.y0 = b.frame.to_px_y(static_cast<double>(geo::tile_origin_y(geo::TileId{z, x, y}))) - margin_px / v.scale;
  v.width = tiles_x * tile_size + 2 * margin_px;
  v.height = tiles_y * tile_size + 2 * margin_px;
  return v;
}

density::Image render_bundle_tile(const Bundled& bundled, const RenderParams& params, int z, int x, int y,
                                  int tile_size) {
  params.validate();
  const int m = tile_margin_px(params);
  const density::Image full =
      render_bundle(bundled, params, tile_viewport(bundled, z, x, y, tile_size, 1, 1, m));
  density::Image out;
  out.width = out.height = tile_size;
  out.rgba.resize(4 * static_cast<std::size_t>(tile_size) * tile_size);
  for (int r = 0; r < tile_size; ++r)
    std::copy_n(full.pixel(m, m + r), 4 * static_cast<std::size_t>(tile_size),
                &out.rgba[4 * static_cast<std::size_t>(r) * tile_size]);
  return out;
}

}  // namespace trailscope::bundling
