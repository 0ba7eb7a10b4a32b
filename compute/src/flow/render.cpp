// Drawing a flow map at a continuous abstraction level (render.hpp).
#include "trailscope/flow/render.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <opencv2/imgproc.hpp>

#include "trailscope/bundling/render.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/density/colormap.hpp"
#include "trailscope/density/renderer.hpp"
#include "trailscope/geo/tile_id.hpp"
#include "trailscope/geo/web_mercator.hpp"

namespace trailscope::flow {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// Premultiplied RGBA float layer.
struct Layer {
  int w, h;
  std::vector<float> px;  // 4 per pixel
  Layer(int w_, int h_) : w(w_), h(h_), px(static_cast<std::size_t>(w_) * h_ * 4, 0.f) {}
  void over(std::size_t p, double r, double g, double b, double a) {
    float* d = &px[p * 4];
    const double k = 1 - a;
    d[0] = static_cast<float>(r * a + d[0] * k), d[1] = static_cast<float>(g * a + d[1] * k);
    d[2] = static_cast<float>(b * a + d[2] * k), d[3] = static_cast<float>(a + d[3] * k);
  }
};

/// A window of output pixels onto a flow map's cell plane: the point at cell coordinates (cx, cy) lies at
/// pixel (cx·scale − off_x[k], cy·scale − off_y), pixel (px, py) covering [px, px+1) × [py, py+1), once for
/// every x offset k (a map tile that sees the grid in two copies of the world, across 180°, has two).
struct LineCanvas {
  int w, h;
  double scale;
  std::vector<double> off_x;
  double off_y;
};

/// Step 2 of render.hpp (the lines layer, premultiplied, at opacity `a1`) on `c`: per line, lightest first,
/// every segment whose pixel box (widened by the line's half width + 1 px) meets the canvas sets the
/// coverage of the pixels it reaches (the most any of the line's segments gives), then the line is
/// composited "over". Segments that miss the canvas cost a bounds test only. A pixel's value depends on
/// the lines and its own position only, so windows that share pixels draw them alike (tiles join).
/// `mask` (w × h, CV_8U): set to 0 where a line covers >= 0.5.
Layer draw_lines(const FlowMap& map, const bundling::Polylines& pl, const LineCanvas& c, double line_width,
                 double a1, cv::Mat* mask) {
  const int W = c.w, H = c.h;
  Layer lines(W, H);
  std::vector<std::size_t> order(pl.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return map.line_traffic[a] < map.line_traffic[b]; });
  const double tmax =
      map.line_traffic.empty()
          ? 1.0
          : std::max(1e-30f, *std::max_element(map.line_traffic.begin(), map.line_traffic.end()));
  std::vector<float> cover(static_cast<std::size_t>(W) * H, 0.f);
  std::vector<float> rgb(static_cast<std::size_t>(W) * H * 3, 0.f);
  std::vector<std::size_t> touched;
  const double s = c.scale;
  for (const std::size_t l : order) {
    const double t = std::sqrt(std::clamp(map.line_traffic[l] / tmax, 0.0, 1.0));
    const double hw = 0.5 * line_width * (0.5 + 1.5 * t);
    const double alpha = 0.25 + 0.75 * t;
    const double r = hw + 1;
    touched.clear();
    for (const double ox : c.off_x)
      for (std::size_t k = pl.begin(l); k + 1 < pl.end(l); ++k) {
        const double x0 = pl.x[k] * s - ox, y0 = pl.y[k] * s - c.off_y;
        const double x1 = pl.x[k + 1] * s - ox, y1 = pl.y[k + 1] * s - c.off_y;
        if (std::max(x0, x1) + r < 0 || std::min(x0, x1) - r > W || std::max(y0, y1) + r < 0 ||
            std::min(y0, y1) - r > H)
          continue;
        const double dx = x1 - x0, dy = y1 - y0, len2 = dx * dx + dy * dy;
        double heading = std::atan2(dx, -dy) / (2 * kPi);
        if (heading < 0) heading += 1;
        const bundling::Rgb col = bundling::hsv_to_rgb(heading, 0.85, 1.0);
        const int px0 = std::max(0, static_cast<int>(std::floor(std::min(x0, x1) - r)));
        const int px1 = std::min(W - 1, static_cast<int>(std::ceil(std::max(x0, x1) + r)));
        const int py0 = std::max(0, static_cast<int>(std::floor(std::min(y0, y1) - r)));
        const int py1 = std::min(H - 1, static_cast<int>(std::ceil(std::max(y0, y1) + r)));
        for (int py = py0; py <= py1; ++py)
          for (int px = px0; px <= px1; ++px) {
            const double cx = px + 0.5, cy = py + 0.5;
            double u = len2 > 0 ? ((cx - x0) * dx + (cy - y0) * dy) / len2 : 0;
            u = std::clamp(u, 0.0, 1.0);
            const double ex = x0 + u * dx - cx, ey = y0 + u * dy - cy;
            const double cov = std::clamp(hw + 0.5 - std::sqrt(ex * ex + ey * ey), 0.0, 1.0);
            if (cov <= 0) continue;
            const std::size_t p = static_cast<std::size_t>(py) * W + px;
            if (cover[p] == 0) touched.push_back(p);
            if (cov > cover[p]) {
              cover[p] = static_cast<float>(cov);
              rgb[3 * p] = static_cast<float>(col[0]), rgb[3 * p + 1] = static_cast<float>(col[1]),
                      rgb[3 * p + 2] = static_cast<float>(col[2]);
            }
          }
      }
    for (const std::size_t p : touched) {
      lines.over(p, rgb[3 * p], rgb[3 * p + 1], rgb[3 * p + 2], alpha * cover[p] * a1);
      if (mask && cover[p] >= 0.5) mask->data[p] = 0;
      cover[p] = 0;
    }
  }
  return lines;
}

/// A premultiplied layer over a transparent background, as straight-alpha 8-bit RGBA (step 4's rounding).
density::Image to_image(const Layer& layer) {
  density::Image out;
  out.width = layer.w, out.height = layer.h;
  out.rgba.resize(static_cast<std::size_t>(layer.w) * layer.h * 4);
  for (std::size_t p = 0; p < static_cast<std::size_t>(layer.w) * layer.h; ++p) {
    const float* q = &layer.px[p * 4];
    const double a = q[3], un = a > 0 ? 1 / a : 0;
    std::uint8_t* o = &out.rgba[p * 4];
    for (int k = 0; k < 3; ++k)
      o[k] = static_cast<std::uint8_t>(std::lround(std::clamp(q[k] * un, 0.0, 1.0) * 255));
    o[3] = static_cast<std::uint8_t>(std::lround(std::clamp(a, 0.0, 1.0) * 255));
  }
  return out;
}

}  // namespace

void FlowRenderParams::validate() const {
  if (!(level >= 0 && level <= 2)) throw invalid_argument("level", "level must be in [0, 2]");
  if (cell_px < 1 || cell_px > 16) throw invalid_argument("cell_px", "cell_px must be 1..16 pixels per cell");
  if (!(line_width >= 0.25 && line_width <= 8))
    throw invalid_argument("line_width", "line_width must be in [0.25, 8] px");
  if (!(halo_px >= 0 && halo_px <= 64)) throw invalid_argument("halo_px", "halo_px must be in [0, 64] px");
  if (background != "black" && background != "transparent")
    throw invalid_argument("background", "background must be black or transparent");
  density::colormap(cmap, "cmap");
}

std::pair<int, int> FlowRenderParams::size(const FlowMap& map) const {
  return size(map.field.grid);
}

std::pair<int, int> FlowRenderParams::size(const Grid& grid) const {
  const long long w = static_cast<long long>(grid.nx) * cell_px;
  const long long h = static_cast<long long>(grid.ny) * cell_px;
  if (w > limits::kMaxFlowImagePx || h > limits::kMaxFlowImagePx)
    throw Error(Error::Kind::payload_too_large, "cell_px",
                "the image would be " + std::to_string(w) + " × " + std::to_string(h) + " px; at most " +
                    std::to_string(limits::kMaxFlowImagePx) + " a side (limits::kMaxFlowImagePx)");
  return {static_cast<int>(w), static_cast<int>(h)};
}

bool FlowRenderParams::set(std::string_view name, std::string_view value) {
  FlowRenderParams p = *this;
  const std::string n(name), v(value);
  const auto num = [&]() {
    std::size_t used = 0;
    double d = 0;
    try {
      d = std::stod(v, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != v.size()) throw invalid_argument(n, n + " must be a number, got '" + v + "'");
    return d;
  };
  if (n == "level")
    p.level = num();
  else if (n == "cell_px") {
    const double d = num();
    if (d != std::floor(d) || d < 1 || d > 16)
      throw invalid_argument("cell_px", "cell_px must be 1..16 pixels per cell");
    p.cell_px = static_cast<int>(d);
  } else if (n == "line_width")
    p.line_width = num();
  else if (n == "halo_px")
    p.halo_px = num();
  else if (n == "background")
    p.background = v;
  else if (n == "cmap")
    p.cmap = v;
  else
    return false;
  p.validate();
  *this = p;
  return true;
}

void set_flow_option(FlowParams& params, FlowRenderParams& render, std::string_view name,
                     std::string_view value) {
  if (!render.set(name, value)) params.set(name, value);
}

namespace {
double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

FlowImage flow_image(const TrailSet& trails, const Query& query, const FlowParams& params,
                     const FlowRenderParams& render, Backend backend, const ProgressFn& progress,
                     const CancelToken* cancel) {
  params.validate();
  render.validate();
  const Grid g = traffic_grid(trails, query, params.field.grid);
  params.check_cost(g.nx, g.ny, params.field.sectors);
  render.size(g);
  FlowImage out;
  out.map = flow_map(trails, query, params, backend, progress, cancel);
  const auto t0 = std::chrono::steady_clock::now();
  out.image = render_flow(out.map, traffic_base(trails, query, out.map, render, params.field.max_gap_seconds),
                          render);
  out.render_ms = ms_since(t0);
  return out;
}

FlowImage flow_image(VectorField field, const FlowParams& params, const FlowRenderParams& render,
                     Backend backend, const ProgressFn& progress, const CancelToken* cancel) {
  params.validate();
  render.validate();
  params.check_cost(field.grid.nx, field.grid.ny, static_cast<int>(field.sectors.size()));
  render.size(field.grid);
  FlowImage out;
  out.map = flow_map(std::move(field), params, backend, progress, cancel);
  const auto t0 = std::chrono::steady_clock::now();
  out.image = render_flow(out.map, field_base(out.map, render), render);
  out.render_ms = ms_since(t0);
  return out;
}

density::Image traffic_base(const TrailSet& trails, const Query& query, const FlowMap& map,
                            const FlowRenderParams& params, double max_gap_seconds) {
  params.validate();
  const Grid& g = map.field.grid;
  if (!g.geographic) throw Error(Error::Kind::unprocessable, "grid", "the density level needs a map grid");
  const auto [w, h] = params.size(map);
  const auto units = std::max<std::int64_t>(1, std::llround(g.cell / params.cell_px));
  const density::Canvas canvas(std::llround(g.x0), std::llround(g.y0), units, w, h);
  density::RenderOptions opt;
  opt.aggregate.max_gap_seconds = max_gap_seconds;
  opt.shade.cmap = params.cmap;
  return density::render_canvas(trails, query, canvas, opt);
}

density::Image field_base(const FlowMap& map, const FlowRenderParams& params) {
  params.validate();
  const auto [w, h] = params.size(map);
  const Grid& g = map.field.grid;
  const std::vector<float> t = total_traffic(map.field);
  density::Raster r;
  r.width = w, r.height = h;
  r.values.resize(static_cast<std::size_t>(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double fx = std::clamp((x + 0.5) / params.cell_px - 0.5, 0.0, g.nx - 1.0);
      const double fy = std::clamp((y + 0.5) / params.cell_px - 0.5, 0.0, g.ny - 1.0);
      const int i0 = std::min(static_cast<int>(fx), g.nx - 2), j0 = std::min(static_cast<int>(fy), g.ny - 2);
      const double ax = fx - i0, ay = fy - j0;
      const auto at = [&](int i, int j) { return static_cast<double>(t[g.index(i, j)]); };
      const double v = (1 - ay) * ((1 - ax) * at(i0, j0) + ax * at(i0 + 1, j0)) +
                       ay * ((1 - ax) * at(i0, j0 + 1) + ax * at(i0 + 1, j0 + 1));
      r.values[static_cast<std::size_t>(y) * w + x] =
          v > 0 ? static_cast<float>(v) : std::numeric_limits<float>::quiet_NaN();
    }
  density::ShadeOptions opt;
  opt.cmap = params.cmap;
  return density::shade(r, density::compute_span(r), opt);
}

density::Image render_flow(const FlowMap& map, const density::Image& base, const FlowRenderParams& params) {
  params.validate();
  const auto [W, H] = params.size(map);
  if (base.width != W || base.height != H)
    throw invalid_argument(
        "base", "the density image must be " + std::to_string(W) + " × " + std::to_string(H) + " px");
  const double L = params.level;
  const bundling::Polylines pl = map.lines_at(L);
  cv::Mat mask(H, W, CV_8U, cv::Scalar(255));  // 0 where a line covers >= 0.5 (distanceTransform's zeros)
  const Layer lines = draw_lines(map, pl, LineCanvas{W, H, static_cast<double>(params.cell_px), {0.0}, 0.0},
                                 params.line_width, std::min(L, 1.0), &mask);

  // 3. The density layer's opacity with the distance-field halo.
  const double a0 = std::max(0.0, 1 - L);
  cv::Mat dist;
  const double halo = params.halo_px * std::min(L, 1.0);
  const bool use_halo = a0 > 0 && halo > 0 && cv::countNonZero(mask) < W * H;
  if (use_halo) cv::distanceTransform(mask, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE);

  // 4. Composite.
  density::Image out;
  out.width = W, out.height = H;
  out.rgba.resize(static_cast<std::size_t>(W) * H * 4);
  const bool black = params.background == "black";
  for (std::size_t p = 0; p < static_cast<std::size_t>(W) * H; ++p) {
    double r = 0, g = 0, b = 0, a = black ? 1 : 0;
    if (a0 > 0) {
      const std::uint8_t* d = &base.rgba[p * 4];
      double da = d[3] / 255.0 * a0;
      if (use_halo)
        da *= std::clamp(dist.at<float>(static_cast<int>(p / W), static_cast<int>(p % W)) / halo, 0.0, 1.0);
      r = d[0] / 255.0 * da + r * (1 - da), g = d[1] / 255.0 * da + g * (1 - da),
      b = d[2] / 255.0 * da + b * (1 - da);
      a = da + a * (1 - da);
    }
    const float* q = &lines.px[p * 4];
    r = q[0] + r * (1 - q[3]), g = q[1] + g * (1 - q[3]), b = q[2] + b * (1 - q[3]),
    a = q[3] + a * (1 - q[3]);
    std::uint8_t* o = &out.rgba[p * 4];
    const double un = a > 0 ? 1 / a : 0;  // straight alpha
    o[0] = static_cast<std::uint8_t>(std::lround(std::clamp(r * un, 0.0, 1.0) * 255));
    o[1] = static_cast<std::uint8_t>(std::lround(std::clamp(g * un, 0.0, 1.0) * 255));
    o[2] = static_cast<std::uint8_t>(std::lround(std::clamp(b * un, 0.0, 1.0) * 255));
    o[3] = static_cast<std::uint8_t>(std::lround(std::clamp(a, 0.0, 1.0) * 255));
  }
  return out;
}

density::Image render_flow_tile(const FlowMap& map, const geo::TileId& tile, int size,
                                const FlowRenderParams& params) {
  params.validate();
  geo::validate_tile(tile);
  if (size != limits::kTileSizeSmall && size != limits::kTileSizeLarge)
    throw invalid_argument("size", "size must be " + std::to_string(limits::kTileSizeSmall) + " or " +
                                       std::to_string(limits::kTileSizeLarge));
  const Grid& g = map.field.grid;
  if (!g.geographic) throw Error(Error::Kind::unprocessable, "grid", "map tiles need a map grid");
  // Mercator units per tile pixel: a power of two (2^(32 − z) / size), so pixel positions are exact.
  const double units = static_cast<double>(geo::tile_size_units(tile.z)) / size;
  const double tx0 = static_cast<double>(geo::tile_origin_x(tile));
  const double ty0 = static_cast<double>(geo::tile_origin_y(tile));
  const double world = static_cast<double>(geo::kWorldUnits);
  const double gx1 = g.x0 + g.nx * g.cell;
  // The grid in every copy of the world the tile sees (a grid across 180° runs past 2^32 in x).
  LineCanvas c{size, size, g.cell / units, {}, (ty0 - g.y0) / units};
  for (const double shift : {-world, 0.0, world}) {
    const double lo = tx0 + shift, hi = lo + size * units;
    if (hi > g.x0 && lo < gx1) c.off_x.push_back((lo - g.x0) / units);
  }
  if (c.off_x.empty() || ty0 + size * units <= g.y0 || ty0 >= g.y0 + g.ny * g.cell)
    return to_image(Layer(size, size));  // the grid does not reach this tile
  const bundling::Polylines pl = map.lines_at(params.level);
  return to_image(draw_lines(map, pl, c, params.line_width, std::min(params.level, 1.0), nullptr));
}

}  // namespace trailscope::flow
