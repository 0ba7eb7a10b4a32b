#pragma once
// Private stages of render_bundle (render.hpp, "EXACTLY WHAT IS COMPUTED"): the density maps (steps
// 2–4 and the lighting of the shaded style) and the line compositor (steps 5–9).
#include <algorithm>
#include <cstddef>
#include <vector>

#include "trailscope/bundling/render.hpp"

namespace trailscope::bundling::detail {

/// Liang–Barsky clipping: narrows [t0, t1] to the parameters t of p + t·d that lie in [lo_x, hi_x] ×
/// [lo_y, hi_y]; false when none do.
inline bool clip_parameters(double px, double py, double dx, double dy, double lo_x, double lo_y, double hi_x,
                            double hi_y, double& t0, double& t1) {
  auto edge = [&](double p, double q) {  // p·t <= q
    if (p == 0) return q >= 0;
    const double r = q / p;
    if (p < 0) {
      if (r > t1) return false;
      t0 = std::max(t0, r);
    } else {
      if (r < t0) return false;
      t1 = std::min(t1, r);
    }
    return true;
  };
  return edge(-dx, px - lo_x) && edge(dx, hi_x - px) && edge(-dy, py - lo_y) && edge(dy, hi_y - py);
}

/// Relaxed polylines in output pixels, plus what the colours need per point.
struct ViewLines {
  Polylines px;                      ///< output pixels
  std::vector<float> displacement;   ///< per point, d of step 6
  std::vector<std::uint32_t> order;  ///< polylines, shortest first
  std::vector<float> len;            ///< per polyline, normalised length (step 5)
};

/// Per-pixel maps, row-major width × height (all empty when the style and colour need no density).
struct DensityMaps {
  int width = 0, height = 0;
  std::vector<float> rho_n;     ///< step 4
  std::vector<float> diffuse;   ///< shaded style only: 0.1 + 0.7·s
  std::vector<float> specular;  ///< shaded style only: 10·s^8
};

/// Steps 2–4 (+ lighting when `lit`).
DensityMaps density_maps(const Polylines& px, int width, int height, const RenderParams& params, bool lit);

/// The square sliding maximum of `v` (w × h) over |dx|, |dy| <= k (values outside count as 0; v >= 0).
std::vector<float> local_max(const std::vector<float>& v, int w, int h, int k);

/// Steps 5–9: composites every polyline over `background` into an RGBA image.
density::Image composite(const Bundled& bundled, const ViewLines& lines, const DensityMaps& maps,
                         const RenderParams& params, int width, int height);

}  // namespace trailscope::bundling::detail
