// C++ reference of each step of the loop (steps.hpp). Compiled with -ffp-contract=off (compute/
// CMakeLists.txt): the kernels in compute/kernels/bundle.cl repeat these expressions operation for
// operation, and an FMA on either side would change the last bit.
#include "bundling/steps.hpp"

#include "bundling/directional.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include "core/rng.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"

namespace trailscope::bundling::detail {
namespace {

double seg_length(const Points& p, std::size_t k) {
  const double dx = static_cast<double>(p.x[k + 1]) - static_cast<double>(p.x[k]);
  const double dy = static_cast<double>(p.y[k + 1]) - static_cast<double>(p.y[k]);
  return std::sqrt(dx * dx + dy * dy);
}

double arc_length(const Points& p, std::uint32_t e) {
  double len = 0;
  for (std::size_t k = p.offsets[e]; k + 1 < p.offsets[e + 1]; ++k) len += seg_length(p, k);
  return len;
}

double now_ms() {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace

Points to_points(const Polylines& px) {
  Points p;
  const std::size_t n = px.points();
  p.x.resize(n), p.y.resize(n), p.z.assign(n, 1.0f), p.edge.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    p.x[i] = static_cast<float>(px.x[i]), p.y[i] = static_cast<float>(px.y[i]);
  p.offsets = px.offsets;
  for (std::size_t e = 0; e < px.size(); ++e)
    for (std::size_t i = px.begin(e); i < px.end(e); ++i) p.edge[i] = static_cast<std::uint32_t>(e);
  return p;
}

Polylines to_polylines(const Points& p) {
  Polylines out;
  out.offsets = p.offsets;
  out.x.assign(p.x.begin(), p.x.end());
  out.y.assign(p.y.begin(), p.y.end());
  return out;
}

double iteration_h(double h, int iterations, int i) {
  const double f = std::pow(2.0 / h, 1.0 / iterations);
  double hi = h;
  for (int k = 0; k < i; ++k) hi *= f;
  return hi;
}

int kernel_radius(double h) {
  return static_cast<int>(h / 2) * 2;
}

std::vector<std::uint64_t> kernel_taps(int radius) {
  std::vector<std::uint64_t> k(2 * radius + 1);
  const std::int64_t r2 = static_cast<std::int64_t>(radius) * radius;
  for (int i = 0; i <= 2 * radius; ++i)
    k[i] = static_cast<std::uint64_t>(r2 - std::int64_t{i - radius} * (i - radius));
  return k;
}

std::vector<float> profile_table(Profile profile) {
  constexpr int kSize = 1024;
  std::vector<float> t(kSize, 1.0f);
  if (profile == Profile::hourglass)
    for (int i = 0; i < kSize; ++i) {
      const double x = std::fabs(i - kSize / 2.0) / (kSize / 2.0);  // 0 at the middle, 1 at the ends
      if (x > 0.7) t[i] = static_cast<float>(std::pow((1 - x) / 0.3, 4));
    }
  return t;
}

std::vector<std::uint32_t> edge_weights(const Polylines& px, DensityMode mode) {
  std::vector<std::uint32_t> w(px.size(), 1);
  if (mode == DensityMode::count) return w;
  std::vector<double> len(px.size(), 0.0);
  double longest = 0;
  for (std::size_t e = 0; e < px.size(); ++e) {
    for (std::size_t k = px.begin(e); k + 1 < px.end(e); ++k)
      len[e] += std::hypot(px.x[k + 1] - px.x[k], px.y[k + 1] - px.y[k]);
    longest = std::max(longest, len[e]);
  }
  if (longest > 0)
    for (std::size_t e = 0; e < px.size(); ++e)
      w[e] = static_cast<std::uint32_t>(std::max(1.0, std::nearbyint(len[e] / longest * kSplatScale)));
  return w;
}

int smooth_window(const BundleParams& p) {
  return static_cast<int>(p.smooth_kernel * p.size / p.spl);
}

double jitter_unit(std::uint64_t seed, std::uint32_t iteration, std::uint32_t edge, std::uint64_t sample) {
  std::uint64_t u = rng::splitmix64_hash(seed ^ (static_cast<std::uint64_t>(iteration) << 40));
  u = rng::splitmix64_hash(u ^ edge);
  u = rng::splitmix64_hash(u ^ sample);
  return static_cast<double>(u >> 11) * 0x1p-52 - 1.0;  // 53 bits: exact, in [−1, 1)
}

std::uint64_t interior_samples(double length, double spl) {
  if (!(length > 0)) return 0;
  double m = std::floor(length / spl);
  if (m * spl >= length) m -= 1;  // strictly inside: a sample at the very end would double the last point
  constexpr double kCap = 2147483648.0;
  return static_cast<std::uint64_t>(std::min(m, kCap));
}

std::vector<std::uint32_t> resample_counts(const Points& in, double spl) {
  std::vector<std::uint32_t> c(in.edges());
  for (std::uint32_t e = 0; e < in.edges(); ++e)
    c[e] = static_cast<std::uint32_t>(2 + interior_samples(arc_length(in, e), spl));
  return c;
}

std::vector<std::uint32_t> resample_offsets(const std::vector<std::uint32_t>& counts) {
  std::vector<std::uint32_t> off(counts.size() + 1);
  std::uint64_t total = 0;
  for (std::size_t e = 0; e < counts.size(); ++e) {
    off[e] = static_cast<std::uint32_t>(total);
    total += counts[e];
    if (total > limits::kMaxBundlePoints)
      throw Error(Error::Kind::payload_too_large, "input",
                  "resampling makes more than " + std::to_string(limits::kMaxBundlePoints) +
                      " points (limits::kMaxBundlePoints); use a larger spl or fewer polylines");
  }
  off[counts.size()] = static_cast<std::uint32_t>(total);
  return off;
}

void resample_edge(const Points& in, std::uint32_t e, const ResampleArgs& a, Points& out) {
  const std::size_t b = in.offsets[e], end = in.offsets[e + 1];
  const std::size_t o = out.offsets[e];
  const std::uint32_t count = out.offsets[e + 1] - out.offsets[e];
  const std::uint64_t n = count - 2;
  auto z_at = [&](std::uint64_t j) {
    if (a.block_endpoints && (j == 0 || j == count - 1)) return 0.0f;
    return a.profile[j * 1023 / (count - 1)];
  };
  out.x[o] = in.x[b], out.y[o] = in.y[b], out.z[o] = z_at(0), out.edge[o] = e;
  const std::size_t last = o + count - 1;
  out.x[last] = in.x[end - 1], out.y[last] = in.y[end - 1], out.z[last] = z_at(count - 1), out.edge[last] = e;
  // Walk the segments once: sample m lies on segment k where start(k) <= m·spl < start(k) + length(k).
  // The lengths are summed in the same order as in resample_counts, so the n-th sample is found before
  // the last segment ends.
  std::size_t k = b;
  double start = 0, len = n > 0 ? seg_length(in, k) : 0;
  for (std::uint64_t m = 1; m <= n; ++m) {
    const double s = static_cast<double>(m) * a.spl;
    while (start + len <= s) {
      start += len;
      ++k;
      len = seg_length(in, k);
    }
    double u = (s - start) + jitter_unit(a.seed, a.iteration, e, m) * (a.jitter * a.spl);
    if (u < 0) u = 0;
    if (u > len) u = len;
    const double t = u / len;
    const double x0 = in.x[k], y0 = in.y[k];
    const double x1 = in.x[k + 1], y1 = in.y[k + 1];
    out.x[o + m] = static_cast<float>(x0 + t * (x1 - x0));
    out.y[o + m] = static_cast<float>(y0 + t * (y1 - y0));
    out.z[o + m] = z_at(m);
    out.edge[o + m] = e;
  }
}

Points resample(const Points& in, const ResampleArgs& a) {
  Points out;
  out.offsets = resample_offsets(resample_counts(in, a.spl));
  const std::size_t total = out.offsets.back();
  out.x.resize(total), out.y.resize(total), out.z.resize(total), out.edge.resize(total);
  for (std::uint32_t e = 0; e < in.edges(); ++e) resample_edge(in, e, a, out);
  return out;
}

Box splat(const Points& p, const std::vector<std::uint32_t>& weights, int size,
          std::vector<std::uint32_t>& img) {
  Box box{size, size, -1, -1};
  const float lim = static_cast<float>(size);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const float x = p.x[i], y = p.y[i];
    if (!(x >= 0.0f && x < lim && y >= 0.0f && y < lim)) continue;  // NaN fails too
    const int ix = static_cast<int>(x), iy = static_cast<int>(y);
    img[static_cast<std::size_t>(iy) * size + ix] += weights[p.edge[i]];
    box.x0 = std::min(box.x0, ix), box.x1 = std::max(box.x1, ix);
    box.y0 = std::min(box.y0, iy), box.y1 = std::max(box.y1, iy);
  }
  return box;
}

Box read_region(const Box& box, int size) {
  if (box.empty()) return box;
  return Box{std::max(0, box.x0 - 2), std::max(0, box.y0 - 2), std::min(size - 1, box.x1 + 2),
             std::min(size - 1, box.y1 + 2)};
}

namespace {

// The sliding window of one pass: Σf, Σj·f, Σj²·f over the window's positions j, modulo 2^64.
struct Moments {
  std::uint64_t a = 0, b = 0, c = 0;
  void add(std::uint64_t j, std::uint64_t f) { a += f, b += j * f, c += j * j * f; }
  void remove(std::uint64_t j, std::uint64_t f) { a -= f, b -= j * f, c -= j * j * f; }
  // Σ f_j·(R² − (x − j)²) = (R² − x²)·Σf + 2x·Σj·f − Σj²·f.
  std::uint64_t at(std::uint64_t x, std::uint64_t r2) const { return r2 * a - x * x * a + 2 * x * b - c; }
};

// One pass along a line: out(x) for x in [x0, x1] from in(j), j in [lo, hi] (zero elsewhere), with
// radius R. `in` and `out` take a position along the line.
template <class In, class Out>
void slide(int x0, int x1, int lo, int hi, int radius, In in, Out out) {
  const std::uint64_t r2 = static_cast<std::uint64_t>(radius) * radius;
  Moments m;
  for (int j = std::max(lo, x0 - radius); j <= std::min(hi, x0 + radius); ++j) m.add(j, in(j));
  for (int x = x0; x <= x1; ++x) {
    if (x > x0) {
      const int gone = x - 1 - radius, come = x + radius;
      if (gone >= lo && gone <= hi) m.remove(gone, in(gone));
      if (come >= lo && come <= hi) m.add(come, in(come));
    }
    out(x, m.at(x, r2));
  }
}

}  // namespace

void convolve(const std::vector<std::uint32_t>& img, int size, const Box& box, int radius,
              std::vector<std::uint64_t>& rows, std::vector<float>& dens) {
  if (box.empty()) return;
  const Box r = read_region(box, size);
  const std::size_t w = static_cast<std::size_t>(size);
  for (int y = box.y0; y <= box.y1; ++y)
    slide(
        r.x0, r.x1, box.x0, box.x1, radius, [&](int j) -> std::uint64_t { return img[y * w + j]; },
        [&](int x, std::uint64_t v) { rows[y * w + x] = v; });
  // Columns: the same walk per column as slide(), done for all columns of the region at once, row by
  // row (the moments of each column in arrays), so that memory is read along rows.
  const std::uint64_t r2 = static_cast<std::uint64_t>(radius) * radius;
  const int nx = r.x1 - r.x0 + 1;
  std::vector<Moments> m(nx);
  auto add_row = [&](int j, bool add) {
    const std::uint64_t* in = rows.data() + j * w + r.x0;
    const std::uint64_t uj = static_cast<std::uint64_t>(j);
    for (int i = 0; i < nx; ++i) add ? m[i].add(uj, in[i]) : m[i].remove(uj, in[i]);
  };
  for (int j = std::max(box.y0, r.y0 - radius); j <= std::min(box.y1, r.y0 + radius); ++j) add_row(j, true);
  for (int y = r.y0; y <= r.y1; ++y) {
    if (y > r.y0) {
      const int gone = y - 1 - radius, come = y + radius;
      if (gone >= box.y0 && gone <= box.y1) add_row(gone, false);
      if (come >= box.y0 && come <= box.y1) add_row(come, true);
    }
    float* out = dens.data() + y * w + r.x0;
    for (int i = 0; i < nx; ++i) out[i] = static_cast<float>(m[i].at(static_cast<std::uint64_t>(y), r2));
  }
}

double sample_density(const std::vector<float>& dens, int size, double sx, double sy) {
  const double u = sx - 0.5, v = sy - 0.5;
  const double fu = std::floor(u), fv = std::floor(v);
  const double ax = u - fu, ay = v - fv;
  const int i0 = static_cast<int>(fu), j0 = static_cast<int>(fv);
  const int xa = std::clamp(i0, 0, size - 1), xb = std::clamp(i0 + 1, 0, size - 1);
  const int ya = std::clamp(j0, 0, size - 1), yb = std::clamp(j0 + 1, 0, size - 1);
  const float* ra = dens.data() + static_cast<std::size_t>(ya) * size;
  const float* rb = dens.data() + static_cast<std::size_t>(yb) * size;
  const double top = (1 - ax) * static_cast<double>(ra[xa]) + ax * static_cast<double>(ra[xb]);
  const double bottom = (1 - ax) * static_cast<double>(rb[xa]) + ax * static_cast<double>(rb[xb]);
  return (1 - ay) * top + ay * bottom;
}

void advect(Points& p, const std::vector<float>& dens, int size, double step) {
  const float lim = static_cast<float>(size);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const float z = p.z[i], xf = p.x[i], yf = p.y[i];
    if (!(z > 0.0f) || !(xf >= 0.0f && xf < lim && yf >= 0.0f && yf < lim)) continue;
    const double x = xf, y = yf;
    // The four samples sample_density(x ± 1, y) and (x, y ± 1), sharing their work: x is a float below
    // 4096, so (x ± 1) − 0.5 = u ± 1 exactly, with the same floor offset and fraction; the samples read
    // the 4 × 4 texels around the point (columns i0−1 .. i0+2, rows j0−1 .. j0+2, each clamped).
    const double u = x - 0.5, v = y - 0.5;
    const double fu = std::floor(u), fv = std::floor(v);
    const double ax = u - fu, ay = v - fv;
    const int i0 = static_cast<int>(fu), j0 = static_cast<int>(fv);
    int c[4], r[4];
    for (int k = 0; k < 4; ++k)
      c[k] = std::clamp(i0 - 1 + k, 0, size - 1), r[k] = std::clamp(j0 - 1 + k, 0, size - 1);
    auto bilinear = [&](int k, int l) {  // the sample whose top-left texel is (c[k], r[l])
      const float* ra = dens.data() + static_cast<std::size_t>(r[l]) * size;
      const float* rb = dens.data() + static_cast<std::size_t>(r[l + 1]) * size;
      const double top = (1 - ax) * static_cast<double>(ra[c[k]]) + ax * static_cast<double>(ra[c[k + 1]]);
      const double bottom = (1 - ax) * static_cast<double>(rb[c[k]]) + ax * static_cast<double>(rb[c[k + 1]]);
      return (1 - ay) * top + ay * bottom;
    };
    const double gx = bilinear(2, 1) - bilinear(0, 1);
    const double gy = bilinear(1, 2) - bilinear(1, 0);
    const double g2 = gx * gx + gy * gy;
    if (g2 < 1e-4) continue;
    const double s = step * static_cast<double>(z) / std::sqrt(g2);
    p.x[i] = static_cast<float>(x + s * gx);
    p.y[i] = static_cast<float>(y + s * gy);
  }
}

void smooth(Points& p, int window, double lambda, int passes) {
  if (window <= 0 || lambda == 0) return;
  std::vector<float> nx(p.size()), ny(p.size());
  for (int pass = 0; pass < passes; ++pass) {
    for (std::size_t i = 0; i < p.size(); ++i) {
      const std::uint32_t e = p.edge[i];
      const std::size_t b = p.offsets[e], end = p.offsets[e + 1];
      const std::size_t lo = i >= b + window ? i - window : b;
      const std::size_t hi = std::min(end - 1, i + window);
      double sx = 0, sy = 0;
      for (std::size_t q = lo; q <= hi; ++q) sx += p.x[q], sy += p.y[q];
      const double n = static_cast<double>(hi - lo + 1);
      const double lz = lambda * static_cast<double>(p.z[i]);
      nx[i] = static_cast<float>((1 - lz) * static_cast<double>(p.x[i]) + lz * (sx / n));
      ny[i] = static_cast<float>((1 - lz) * static_cast<double>(p.y[i]) + lz * (sy / n));
    }
    p.x.swap(nx);
    p.y.swap(ny);
  }
}

Points run_loop_ref(Points pts, const BundleParams& params, const std::vector<std::uint32_t>& weights,
                    LoopTimes& times, const ProgressFn& progress, const CancelToken* cancel) {
  const std::vector<float> profile = profile_table(params.profile);
  const int size = params.size;
  const std::size_t pixels = static_cast<std::size_t>(size) * size;
  std::vector<std::uint32_t> img(pixels);
  std::vector<std::uint64_t> rows(pixels);
  std::vector<float> dens(pixels);
  const int window = smooth_window(params);
  for (int it = 0; it < params.iterations; ++it) {
    if (cancel) cancel->throw_if_cancelled();
    const double h = iteration_h(params.h, params.iterations, it);
    double t0 = now_ms();
    if (it == 0 || !params.polyline_style) {
      ResampleArgs a;
      a.spl = params.spl, a.jitter = params.jitter, a.seed = params.seed;
      a.iteration = static_cast<std::uint32_t>(it), a.block_endpoints = params.block_endpoints;
      a.profile = profile.data();
      pts = resample(pts, a);
    }
    double t1 = now_ms();
    times.resample_ms += t1 - t0;
    if (params.directional) {
      // Directional: the site map and directions replace the density (all booked as advection).
      site_map(pts, size, img);
      advect_directional(pts, img, point_directions(pts), size, kernel_radius(h), params.eps * h,
                         params.repulsion);
      t0 = now_ms();
      times.advect_ms += t0 - t1;
    } else {
      std::fill(img.begin(), img.end(), 0u);
      const Box box = splat(pts, weights, size, img);
      t0 = now_ms();
      times.splat_ms += t0 - t1;
      convolve(img, size, box, kernel_radius(h), rows, dens);
      t1 = now_ms();
      times.convolve_ms += t1 - t0;
      advect(pts, dens, size, params.eps * h);
      t0 = now_ms();
      times.advect_ms += t0 - t1;
    }
    smooth(pts, window, params.lambda, params.smooth_iterations);
    times.smooth_ms += now_ms() - t0;
    if (progress) progress(static_cast<double>(it + 1) / params.iterations, "bundle");
  }
  return pts;
}

void run_fixed_ref(Points& pts, const std::vector<std::uint32_t>& weights, const FixedArgs& a,
                   LoopTimes& times) {
  const std::size_t pixels = static_cast<std::size_t>(a.size) * a.size;
  std::vector<std::uint32_t> img(pixels);
  std::vector<std::uint64_t> rows(pixels);
  std::vector<float> dens(pixels);
  for (int it = 0; it < a.iterations; ++it) {
    double t0 = now_ms();
    std::fill(img.begin(), img.end(), 0u);
    const Box box = splat(pts, weights, a.size, img);
    double t1 = now_ms();
    times.splat_ms += t1 - t0;
    convolve(img, a.size, box, a.radius, rows, dens);
    t0 = now_ms();
    times.convolve_ms += t0 - t1;
    advect(pts, dens, a.size, a.step);
    t1 = now_ms();
    times.advect_ms += t1 - t0;
    smooth(pts, a.window, a.lambda, a.passes);
    times.smooth_ms += now_ms() - t1;
  }
}

}  // namespace trailscope::bundling::detail
