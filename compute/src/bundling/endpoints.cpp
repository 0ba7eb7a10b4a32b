// Endpoint mean-shift clustering (endpoints.hpp).
#include "bundling/endpoints.hpp"

#include <algorithm>
#include <cmath>

namespace trailscope::bundling::detail {
namespace {

// One mean-shift move of every endpoint. The loop's advection takes a fixed step eps·h along the
// normalised gradient, which makes two groups of endpoints a few pixels apart jump over each other
// and oscillate instead of meeting. Near a cluster the Epanechnikov density is a quadratic whose
// maximum is the cluster's weighted mean, so the Newton step −g/ρ'' (central differences) lands on it:
// the move is the fixed step, or the Newton step when that is shorter and the density is concave in
// both axes.
void mean_shift_step(Points& p, const std::vector<float>& dens, int size, double step) {
  const float lim = static_cast<float>(size);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double x = p.x[i], y = p.y[i];
    if (!(p.x[i] >= 0.0f && p.x[i] < lim && p.y[i] >= 0.0f && p.y[i] < lim)) continue;
    const double c = sample_density(dens, size, x, y);
    const double xp = sample_density(dens, size, x + 1, y), xm = sample_density(dens, size, x - 1, y);
    const double yp = sample_density(dens, size, x, y + 1), ym = sample_density(dens, size, x, y - 1);
    const double gx = xp - xm, gy = yp - ym;
    const double g = std::sqrt(gx * gx + gy * gy);
    if (g * g < 1e-4) continue;
    double dx = step * gx / g, dy = step * gy / g;
    const double hxx = xp - 2 * c + xm, hyy = yp - 2 * c + ym;
    if (hxx < 0 && hyy < 0) {
      const double nx = -0.5 * gx / hxx, ny = -0.5 * gy / hyy;  // g is twice the central difference
      if (std::hypot(nx, ny) < step) dx = nx, dy = ny;
    }
    p.x[i] = static_cast<float>(x + dx);
    p.y[i] = static_cast<float>(y + dy);
  }
}

}  // namespace

Points mean_shift_endpoints(const Points& pts, const BundleParams& params,
                            const std::vector<std::uint32_t>& weights, const ProgressFn& progress,
                            const CancelToken* cancel) {
  Points ends;
  const std::size_t edges = pts.edges();
  ends.x.resize(2 * edges), ends.y.resize(2 * edges), ends.z.assign(2 * edges, 1.0f),
      ends.edge.resize(2 * edges);
  ends.offsets.resize(edges + 1);
  for (std::size_t e = 0; e < edges; ++e) {
    const std::size_t b = pts.offsets[e], last = pts.offsets[e + 1] - 1;
    ends.x[2 * e] = pts.x[b], ends.y[2 * e] = pts.y[b];
    ends.x[2 * e + 1] = pts.x[last], ends.y[2 * e + 1] = pts.y[last];
    ends.edge[2 * e] = ends.edge[2 * e + 1] = static_cast<std::uint32_t>(e);
    ends.offsets[e + 1] = static_cast<std::uint32_t>(2 * e + 2);
  }
  const int size = params.size;
  const std::size_t pixels = static_cast<std::size_t>(size) * size;
  std::vector<std::uint32_t> img(pixels);
  std::vector<std::uint64_t> rows(pixels);
  std::vector<float> dens(pixels);
  for (int it = 0; it < params.ms_iterations; ++it) {
    if (cancel) cancel->throw_if_cancelled();
    const double h = iteration_h(params.ms_h, params.ms_iterations, it);
    std::fill(img.begin(), img.end(), 0u);
    const Box box = splat(ends, weights, size, img);
    convolve(img, size, box, kernel_radius(h), rows, dens);
    mean_shift_step(ends, dens, size, params.eps * h);
    if (progress) progress(static_cast<double>(it + 1) / params.ms_iterations, "endpoints");
  }
  return ends;
}

Points cluster_endpoints(const Points& pts, const BundleParams& params,
                         const std::vector<std::uint32_t>& weights, const ProgressFn& progress,
                         const CancelToken* cancel) {
  const Points ends = mean_shift_endpoints(pts, params, weights, progress, cancel);
  Points out;
  const std::size_t edges = pts.edges();
  out.offsets.assign(1, 0);
  auto push = [&](float x, float y, std::uint32_t e) {
    out.x.push_back(x), out.y.push_back(y), out.z.push_back(1.0f), out.edge.push_back(e);
  };
  for (std::size_t e = 0; e < edges; ++e) {
    const std::uint32_t ue = static_cast<std::uint32_t>(e);
    const std::size_t b = pts.offsets[e], end = pts.offsets[e + 1];
    push(pts.x[b], pts.y[b], ue);
    push(ends.x[2 * e], ends.y[2 * e], ue);
    for (std::size_t i = b + 1; i + 1 < end; ++i) push(pts.x[i], pts.y[i], ue);
    push(ends.x[2 * e + 1], ends.y[2 * e + 1], ue);
    push(pts.x[end - 1], pts.y[end - 1], ue);
    out.offsets.push_back(static_cast<std::uint32_t>(out.x.size()));
  }
  return out;
}

void smooth_ends(Points& pts, const BundleParams& params) {
  const int window = static_cast<int>(params.ms_h / params.spl);
  if (window <= 0 || params.lambda_ends == 0) return;
  const std::vector<float> x = pts.x, y = pts.y;
  std::vector<double> cum;
  for (std::size_t e = 0; e < pts.edges(); ++e) {
    const std::size_t b = pts.offsets[e], end = pts.offsets[e + 1];
    cum.assign(end - b, 0.0);
    for (std::size_t i = b + 1; i < end; ++i)
      cum[i - b] = cum[i - b - 1] +
                   std::hypot(static_cast<double>(x[i]) - x[i - 1], static_cast<double>(y[i]) - y[i - 1]);
    const double total = cum.back();
    for (std::size_t i = b + 1; i + 1 < end; ++i) {
      const double from_end = std::min(cum[i - b], total - cum[i - b]);
      if (from_end > params.ms_h) continue;
      const std::size_t lo = i >= b + window ? i - window : b, hi = std::min(end - 1, i + window);
      double sx = 0, sy = 0;
      for (std::size_t q = lo; q <= hi; ++q) sx += x[q], sy += y[q];
      const double n = static_cast<double>(hi - lo + 1), l = params.lambda_ends;
      pts.x[i] = static_cast<float>((1 - l) * x[i] + l * (sx / n));
      pts.y[i] = static_cast<float>((1 - l) * y[i] + l * (sy / n));
    }
  }
}

}  // namespace trailscope::bundling::detail
