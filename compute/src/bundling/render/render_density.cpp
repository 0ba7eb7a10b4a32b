// Steps 2–4 of render.hpp: the line density of the drawn polylines, its smoothing, the local-maximum
// normalisation, and the lighting of the shaded style.
//
// The density reuses the density path's exact integer walk (density_lines.hpp) on a canvas whose "units"
// are 1/256 output pixel: the walk decides pixels from the segment and the global pixel grid only, so a
// polyline touches the same pixels whichever tile or viewport draws it (tiles have no seams), and each
// polyline adds exactly 1 to every pixel it passes (runs count shared vertices once).
#include <algorithm>
#include <cmath>
#include <deque>

#include "bundling/render/render_detail.hpp"
#include "trailscope/density/kde.hpp"
#include "trailscope/density/raster.hpp"

namespace trailscope::bundling::detail {
namespace {

constexpr std::int64_t kSub = 256;  ///< walk units per output pixel
/// Coordinates beyond this many pixels from the image are clipped before quantising, so that the
/// quantised endpoints of one segment stay within 2^31 units (append_segment would otherwise read the
/// segment as crossing 180°). Far enough out that the clipped line is the same to well below 1/256 px.
constexpr double kFar = 1 << 21;

/// Liang–Barsky clip of p0 → p1 to [lo_x, hi_x] × [lo_y, hi_y]; false when nothing is left.
bool clip(double& x0, double& y0, double& x1, double& y1, double lo_x, double lo_y, double hi_x, double hi_y,
          bool& start_moved, bool& end_moved) {
  double t0 = 0, t1 = 1;
  const double dx = x1 - x0, dy = y1 - y0;
  if (!detail::clip_parameters(x0, y0, dx, dy, lo_x, lo_y, hi_x, hi_y, t0, t1)) return false;
  start_moved = t0 > 0, end_moved = t1 < 1;
  const double ax = x0 + t0 * dx, ay = y0 + t0 * dy, bx = x0 + t1 * dx, by = y0 + t1 * dy;
  x0 = ax, y0 = ay, x1 = bx, y1 = by;
  return true;
}

/// ρ: passes of polylines per pixel.
density::Aggregate line_density(const Polylines& px, int width, int height) {
  const density::Canvas canvas(0, 0, kSub, width, height);
  density::LineSegments segs = density::LineSegments::for_canvas(canvas, false);
  const double lo_x = -kFar, lo_y = -kFar, hi_x = width + kFar, hi_y = height + kFar;
  for (std::size_t i = 0; i < px.size(); ++i) {
    bool run_open = false;  // the previous segment ended, unclipped, where this one starts
    for (std::size_t k = px.begin(i); k + 1 < px.end(i); ++k) {
      double x0 = px.x[k], y0 = px.y[k], x1 = px.x[k + 1], y1 = px.y[k + 1];
      if (!std::isfinite(x0) || !std::isfinite(y0) || !std::isfinite(x1) || !std::isfinite(y1)) {
        run_open = false;
        continue;
      }
      bool start_moved = false, end_moved = false;
      if (!clip(x0, y0, x1, y1, lo_x, lo_y, hi_x, hi_y, start_moved, end_moved)) {
        run_open = false;
        continue;
      }
      const density::MercPoint a{std::llround(x0 * kSub), std::llround(y0 * kSub)};
      const density::MercPoint b{std::llround(x1 * kSub), std::llround(y1 * kSub)};
      density::append_segment(segs, canvas, a, b, run_open && !start_moved);
      run_open = !end_moved;
    }
  }
  return density::density_lines_ref(segs);
}

}  // namespace

std::vector<float> local_max(const std::vector<float>& v, int w, int h, int k) {
  std::vector<float> rows(v.size()), out(v.size());
  std::vector<int> dq(static_cast<std::size_t>(std::max(w, h)));
  // Monotonic-deque sliding maximum over a line of n values at stride `step` (van Herk's O(n) idea with
  // a deque): out[j] = max in[j−k .. j+k] ∩ [0, n).
  auto line = [&](const float* in, float* o, int n, std::size_t step) {
    int head = 0, tail = 0;
    for (int i = 0; i < n + k; ++i) {
      if (i < n) {
        while (tail > head && in[dq[tail - 1] * step] <= in[i * step]) --tail;
        dq[tail++] = i;
      }
      const int j = i - k;
      if (j < 0) continue;
      while (dq[head] < j - k) ++head;
      o[j * step] = in[dq[head] * step];
    }
  };
  for (int y = 0; y < h; ++y)
    line(&v[static_cast<std::size_t>(y) * w], &rows[static_cast<std::size_t>(y) * w], w, 1);
  for (int x = 0; x < w; ++x) line(&rows[x], &out[x], h, static_cast<std::size_t>(w));
  return out;
}

DensityMaps density_maps(const Polylines& px, int width, int height, const RenderParams& params, bool lit) {
  DensityMaps m;
  m.width = width, m.height = height;
  const density::Aggregate agg = line_density(px, width, height);
  const std::size_t n = static_cast<std::size_t>(width) * height;
  std::vector<float> rho(n);
  if (params.shading_radius > 0) {
    const density::Raster r = density::kde_smooth(agg, density::DensityValue::count, params.shading_radius);
    for (std::size_t i = 0; i < n; ++i) rho[i] = std::isnan(r.values[i]) ? 0.0f : r.values[i];
  } else {
    for (std::size_t i = 0; i < n; ++i) rho[i] = static_cast<float>(agg.count[i]);
  }
  const std::vector<float> mx =
      local_max(rho, width, height, static_cast<int>(std::floor(params.local_max_radius)));
  m.rho_n.resize(n);
  for (std::size_t i = 0; i < n; ++i) m.rho_n[i] = mx[i] > 0 ? rho[i] / mx[i] : 0.0f;
  if (!lit) return m;

  m.diffuse.resize(n), m.specular.resize(n);
  const double relief = kRelief * std::max(1.0, params.shading_radius);
  auto at = [&](int x, int y) {  // clamped to the image: the edge continues flat
    x = std::clamp(x, 0, width - 1), y = std::clamp(y, 0, height - 1);
    return static_cast<double>(m.rho_n[static_cast<std::size_t>(y) * width + x]);
  };
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double gx = relief * (at(x + 1, y) - at(x - 1, y)) / 2;
      const double gy = relief * (at(x, y + 1) - at(x, y - 1)) / 2;
      const Lighting l = light(gx, gy);
      const std::size_t i = static_cast<std::size_t>(y) * width + x;
      m.diffuse[i] = static_cast<float>(l.diffuse);
      m.specular[i] = static_cast<float>(l.specular);
    }
  return m;
}

}  // namespace trailscope::bundling::detail
