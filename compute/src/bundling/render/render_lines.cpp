// Steps 5–9 of render.hpp: per-point colours and alphas, anti-aliased lines, "over" compositing.
//
// WHY A SMALL RASTERISER OF OUR OWN rather than cv::line(LINE_AA): OpenCV anti-aliases only 8-bit
// images (other depths fall back to aliased lines), draws one colour per call (CUBu interpolates colour
// and alpha along every segment, as GL_LINE_STRIP does), and blends each call into the image at once,
// so a polyline's joints would be composited twice. Here a polyline first collects its fragments (pixel,
// coverage, colour, alpha; the nearest segment wins where its segments overlap) and is then composited
// once per pixel. Coverage is a function of the pixel centre's distance to the segment alone, so it does
// not depend on which viewport or tile draws the line: tiles have no seams.
#include <algorithm>
#include <cmath>
#include <limits>

#include "bundling/render/render_detail.hpp"
#include "trailscope/density/colormap.hpp"

namespace trailscope::bundling::detail {
namespace {

/// A vertex's premultiplied-by-luminance colour and its alpha (step 7 without the per-pixel factors).
struct Vertex {
  float r, g, b, a;
};

struct Fragment {
  std::uint32_t pixel;
  float closeness;  ///< line_width/2 + 0.5 − distance; the coverage is min(1, closeness)
  Vertex c;
};

/// Longest piece a segment is cut into for enumerating pixels (px): keeps the bounding box of a diagonal
/// piece small without many pieces.
constexpr double kPiece = 16;

Rgb cmap_rgb(const density::Colormap& cm, double v) {
  const auto& c = cm.rgb[static_cast<std::size_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0))];
  return {c[0] / 255.0, c[1] / 255.0, c[2] / 255.0};
}

double mode_factor(AlphaMode m, double v) {
  switch (m) {
    case AlphaMode::constant:
      return 1;
    case AlphaMode::value:
      return v;
    case AlphaMode::inverse:
      return 1 - v;
  }
  return 1;
}

class Collector {
 public:
  Collector(int width, int height)
      : w_(width),
        h_(height),
        stamp_(static_cast<std::size_t>(width) * height, kNone),
        slot_(static_cast<std::size_t>(width) * height) {}

  void begin(std::uint32_t polyline) { id_ = polyline, frags_.clear(); }
  const std::vector<Fragment>& fragments() const { return frags_; }

  /// Adds the fragments of segment p → q (vertex attributes cp, cq) of half width hw.
  void segment(double px, double py, double qx, double qy, const Vertex& cp, const Vertex& cq, double hw) {
    const double dx = qx - px, dy = qy - py, len2 = dx * dx + dy * dy;
    const double reach = hw + 0.5;
    // The parameter range of the segment within the image grown by `reach` (Liang–Barsky).
    double t0 = 0, t1 = 1;
    if (!clip_parameters(px, py, dx, dy, -reach, -reach, w_ + reach, h_ + reach, t0, t1)) return;
    const double length = std::sqrt(len2) * (t1 - t0);
    const int pieces = std::max(1, static_cast<int>(std::ceil(length / kPiece)));
    for (int k = 0; k < pieces; ++k) {
      const double a = t0 + (t1 - t0) * k / pieces, b = t0 + (t1 - t0) * (k + 1) / pieces;
      const double ax = px + a * dx, ay = py + a * dy, bx = px + b * dx, by = py + b * dy;
      const int x_lo = std::max(0, static_cast<int>(std::floor(std::min(ax, bx) - reach)));
      const int x_hi = std::min(w_ - 1, static_cast<int>(std::floor(std::max(ax, bx) + reach)));
      const int y_lo = std::max(0, static_cast<int>(std::floor(std::min(ay, by) - reach)));
      const int y_hi = std::min(h_ - 1, static_cast<int>(std::floor(std::max(ay, by) + reach)));
      if (len2 == 0) {
        for (int y = y_lo; y <= y_hi; ++y)
          for (int x = x_lo; x <= x_hi; ++x) visit(x, y, px, py, dx, dy, len2, reach, cp, cq);
      } else if (std::fabs(dx) >= std::fabs(dy)) {
        // Only the pixels whose centre lies in the strip |distance to the line| < reach (a superset of
        // the capsule around the segment): per column, rows around the line's height there.
        const double h = reach * std::sqrt(len2) / std::fabs(dx);
        for (int x = x_lo; x <= x_hi; ++x) {
          const double yl = py + (x + 0.5 - px) * dy / dx;
          const int r0 = std::max(y_lo, static_cast<int>(std::floor(yl - h - 0.5)));
          const int r1 = std::min(y_hi, static_cast<int>(std::ceil(yl + h - 0.5)));
          for (int y = r0; y <= r1; ++y) visit(x, y, px, py, dx, dy, len2, reach, cp, cq);
        }
      } else {
        const double h = reach * std::sqrt(len2) / std::fabs(dy);
        for (int y = y_lo; y <= y_hi; ++y) {
          const double xl = px + (y + 0.5 - py) * dx / dy;
          const int c0 = std::max(x_lo, static_cast<int>(std::floor(xl - h - 0.5)));
          const int c1 = std::min(x_hi, static_cast<int>(std::ceil(xl + h - 0.5)));
          for (int x = c0; x <= c1; ++x) visit(x, y, px, py, dx, dy, len2, reach, cp, cq);
        }
      }
    }
  }

 private:
  /// Pixel (x, y) against the whole segment p + t·d (not the piece), so the result does not depend on
  /// where the pieces were cut or which pixels were enumerated.
  void visit(int x, int y, double px, double py, double dx, double dy, double len2, double reach,
             const Vertex& cp, const Vertex& cq) {
    const double cx = x + 0.5 - px, cy = y + 0.5 - py;
    const double t = len2 > 0 ? std::clamp((cx * dx + cy * dy) / len2, 0.0, 1.0) : 0.0;
    const double ex = cx - t * dx, ey = cy - t * dy;
    const double closeness = reach - std::sqrt(ex * ex + ey * ey);  // coverage before clamping to 1
    if (closeness <= 0) return;
    const auto ft = static_cast<float>(t);
    add(static_cast<std::uint32_t>(y * w_ + x), static_cast<float>(closeness),
        Vertex{cp.r + (cq.r - cp.r) * ft, cp.g + (cq.g - cp.g) * ft, cp.b + (cq.b - cp.b) * ft,
               cp.a + (cq.a - cp.a) * ft});
  }
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  /// Keeps, per pixel, the fragment of the segment nearest to its centre: the largest coverage, and
  /// among fully covered ones (thick lines) the closest, so the colour is that of the nearest point.
  void add(std::uint32_t pixel, float closeness, const Vertex& c) {
    if (stamp_[pixel] != id_) {
      stamp_[pixel] = id_;
      slot_[pixel] = static_cast<std::uint32_t>(frags_.size());
      frags_.push_back(Fragment{pixel, closeness, c});
    } else if (Fragment& f = frags_[slot_[pixel]]; closeness > f.closeness) {
      f.closeness = closeness, f.c = c;
    }
  }
  int w_, h_;
  std::uint32_t id_ = kNone;
  std::vector<std::uint32_t> stamp_, slot_;
  std::vector<Fragment> frags_;
};

}  // namespace

density::Image composite(const Bundled& bundled, const ViewLines& lines, const DensityMaps& maps,
                         const RenderParams& params, int width, int height) {
  const std::size_t n = static_cast<std::size_t>(width) * height;
  std::vector<float> acc(4 * n, 0.0f);  // premultiplied r, g, b, a
  const bool per_pixel_colour = params.color == ColorBy::density;
  const density::Colormap* cm = (params.color == ColorBy::density || params.color == ColorBy::displacement)
                                    ? &density::colormap(params.cmap)
                                    : nullptr;
  const double hw = params.line_width / 2;
  const Polylines& px = lines.px;
  Collector collect(width, height);
  std::vector<Vertex> vtx;

  for (const std::uint32_t i : lines.order) {
    const std::size_t b = px.begin(i), e = px.end(i);
    const double len = lines.len[i];
    Rgb base{0.9, 0.9, 0.9};
    if (params.color == ColorBy::length) base = rainbow(len);
    if (params.color == ColorBy::direction)
      base = hsv_to_rgb(bundled.angle[i] / (2 * M_PI), std::pow(len, 0.3), 1);
    vtx.resize(e - b);
    for (std::size_t k = b; k < e; ++k) {
      const Cushion c = cushion(len, bundled.t[k]);
      Rgb rgb = base;
      double value = len, lum = c.luminance;
      if (params.color == ColorBy::displacement) value = lines.displacement[k], rgb = cmap_rgb(*cm, value);
      // With the density colour, colour and value come from ρn at each pixel (below).
      if (per_pixel_colour) lum = 1;
      const double mode = per_pixel_colour ? 1.0 : mode_factor(params.alpha_mode, value);
      const double a = params.alpha * mode * c.alpha;
      vtx[k - b] = Vertex{static_cast<float>(rgb[0] * lum), static_cast<float>(rgb[1] * lum),
                          static_cast<float>(rgb[2] * lum), static_cast<float>(a)};
    }
    collect.begin(i);
    for (std::size_t k = b; k + 1 < e; ++k) {
      const double x0 = px.x[k], y0 = px.y[k], x1 = px.x[k + 1], y1 = px.y[k + 1];
      if (!std::isfinite(x0) || !std::isfinite(y0) || !std::isfinite(x1) || !std::isfinite(y1)) continue;
      collect.segment(x0, y0, x1, y1, vtx[k - b], vtx[k + 1 - b], hw);
    }
    for (const Fragment& f : collect.fragments()) {
      const double rho = maps.rho_n.empty() ? 1.0 : maps.rho_n[f.pixel];  // empty: not needed
      double r = f.c.r, g = f.c.g, bl = f.c.b, a = f.c.a;
      if (per_pixel_colour) {
        const Rgb c = cmap_rgb(*cm, rho);
        r = c[0], g = c[1], bl = c[2];
        a *= mode_factor(params.alpha_mode, rho);
      }
      if (params.alpha_by_density) a *= std::pow(rho, 0.3);
      if (params.style == Style::shaded) {
        // The highlight is tinted by the line's colour (a metallic material) rather than white, and the
        // lit colour is brought back into range by its largest channel, which keeps hue and saturation:
        // a thin line sits on its own density ridge, where the surface is flat and 10·s^8 ≈ 3.3, so a
        // white highlight (or a per-channel clamp) would wash every isolated line out to white.
        const double k = maps.diffuse[f.pixel] + maps.specular[f.pixel];
        r *= k, g *= k, bl *= k;
        if (const double top = std::max({r, g, bl}); top > 1) r /= top, g /= top, bl /= top;
      } else if (params.style == Style::tube) {
        r *= rho, g *= rho, bl *= rho;
      }
      a = std::clamp(a * std::min(1.0f, f.closeness), 0.0, 1.0);
      float* p = &acc[4 * static_cast<std::size_t>(f.pixel)];
      const auto fa = static_cast<float>(a), keep = 1.0f - fa;
      p[0] = static_cast<float>(r) * fa + p[0] * keep;
      p[1] = static_cast<float>(g) * fa + p[1] * keep;
      p[2] = static_cast<float>(bl) * fa + p[2] * keep;
      p[3] = fa + p[3] * keep;
    }
  }

  density::Image img;
  img.width = width, img.height = height;
  img.rgba.resize(4 * n);
  auto byte = [](double v) {
    return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0));
  };
  for (std::size_t i = 0; i < n; ++i) {
    const float* p = &acc[4 * i];
    std::uint8_t* o = &img.rgba[4 * i];
    if (params.background == "transparent") {
      for (int c = 0; c < 3; ++c) o[c] = p[3] > 0 ? byte(p[c] / p[3]) : 0;
      o[3] = byte(p[3]);
    } else {
      const double bg = params.background == "white" ? 1.0 : 0.0;
      for (int c = 0; c < 3; ++c) o[c] = byte(p[c] + bg * (1 - p[3]));
      o[3] = 255;
    }
  }
  return img;
}

}  // namespace trailscope::bundling::detail
