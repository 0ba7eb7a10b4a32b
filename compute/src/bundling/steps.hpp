#pragma once
// The steps of the CUBu loop (bundle.hpp, THE LOOP) as plain single-threaded C++: the reference that
// compute/kernels/bundle.cl must match BIT FOR BIT. Every step is written so that the kernel can do the
// same IEEE operations in the same order:
//  - points are float x, y, z (z: the profile weight in [0, 1]) with the owning polyline's index per
//    point and an offsets table (the device layout);
//  - geometry (arc length, sample placement, advection, smoothing means) is computed in double from the
//    float values and rounded to float once, on store; this file and the kernels are compiled with
//    floating-point contraction off (no fused multiply-add), and double +, −, ×, ÷ and sqrt are
//    correctly rounded on both sides;
//  - splats and the convolution are exact unsigned 64-bit integer arithmetic (order-free): the kernel
//    taps are the integers R² − d² (the Epanechnikov 1 − (d/R)² times R², the original's taps up to a
//    constant factor, which the normalised gradient ignores), and each pass is a sliding window of
//    the three moments Σf, Σj·f, Σj²·f, O(1) per pixel whatever the radius. The sums are taken modulo
//    2^64; the result is exact whenever the true value is below 2^64, which holds whenever the total
//    splat weight times R⁴ is below 2^64 (64 M points of weight 1024 at R = 128 would just reach it).
//    The density is then rounded to float once (advection reads floats).
// Private to compute/ (tests include it by relative path to test each step).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "trailscope/bundling/params.hpp"
#include "trailscope/bundling/polylines.hpp"
#include "trailscope/core/progress.hpp"

namespace trailscope::bundling::detail {

/// Points of every polyline, flat, in the layout the kernels read.
struct Points {
  std::vector<float> x, y, z;
  std::vector<std::uint32_t> edge;        ///< per point, the index of its polyline
  std::vector<std::uint32_t> offsets{0};  ///< per polyline + 1: polyline e is offsets[e] .. offsets[e+1]−1

  std::size_t size() const { return x.size(); }
  std::size_t edges() const { return offsets.size() - 1; }
};

/// Inclusive pixel box of the splatted points; empty when x0 > x1.
struct Box {
  int x0 = 1, y0 = 1, x1 = 0, y1 = 0;
  bool empty() const { return x0 > x1; }
};

/// The input polylines as Points (coordinates rounded to float; z = 1, resampling sets it).
Points to_points(const Polylines& px);
/// Back to double polylines.
Polylines to_polylines(const Points& p);

// --- per-call constants ---------------------------------------------------------------------------------
/// Kernel radius of iteration i: h · f^i with f = (2/h)^(1/iterations), by repeated multiplication (as the
/// original's h_kern *= h_fact). At the last iteration it is 2/f (≈ 2.4 px for the defaults).
double iteration_h(double h, int iterations, int i);
/// Taps radius of kernel size h: int(h/2)·2 (even, >= 2 for h >= 2).
int kernel_radius(double h);
/// The 2R+1 Epanechnikov taps as integers: K[i] = R² − (i − R)² = R²·(1 − x²) with x = |i/(Lk−1) − 0.5|/0.5,
/// the original's taps times R² (K[0] = K[2R] = 0). What convolve() computes, written out (tests).
std::vector<std::uint64_t> kernel_taps(int radius);
/// The 1024-entry edge profile (z along an edge by arc-length index).
std::vector<float> profile_table(Profile profile);
/// Per polyline, its splat weight: `count` 1; `weighted` max(1, round(length/max_length · kSplatScale))
/// from the arc lengths of `px` (the original input).
std::vector<std::uint32_t> edge_weights(const Polylines& px, DensityMode mode);
/// Laplacian half-window in points: int(smooth_kernel · size / spl).
int smooth_window(const BundleParams& p);

// --- resample ---------------------------------------------------------------------------------------------
/// The jitter of sample `sample` of polyline `edge` in iteration `iteration`, uniform in [−1, 1): a pure
/// function of its arguments (splitmix64 chain), so the result does not depend on threads or device.
double jitter_unit(std::uint64_t seed, std::uint32_t iteration, std::uint32_t edge, std::uint64_t sample);

/// Interior samples of a polyline of arc length L at step spl: the m >= 1 with m·spl < L (0 when L <= 0),
/// capped at 2^31 (a count that large is over every limit anyway).
std::uint64_t interior_samples(double length, double spl);

struct ResampleArgs {
  double spl = 15, jitter = 0.25;
  std::uint64_t seed = 1;
  std::uint32_t iteration = 0;
  bool block_endpoints = true;
  const float* profile = nullptr;  ///< 1024 entries
};
/// Points per polyline after resampling: 2 + interior_samples(arc length of the float points).
std::vector<std::uint32_t> resample_counts(const Points& in, double spl);
/// The new offsets from the counts (exclusive scan). Throws Error(payload_too_large, `input`) when the
/// total exceeds limits::kMaxBundlePoints — before anything of that size is allocated.
std::vector<std::uint32_t> resample_offsets(const std::vector<std::uint32_t>& counts);
/// Resamples polyline e of `in` into out[offsets[e] ..]: the first point, samples m = 1..n at arc length
/// m·spl (each shifted along its segment by jitter_unit·jitter·spl, clamped to the segment), the last
/// point; z from the profile at index j·1023/(count−1), 0 at both ends with block_endpoints.
void resample_edge(const Points& in, std::uint32_t e, const ResampleArgs& a, Points& out);
/// count + scan + place for every polyline.
Points resample(const Points& in, const ResampleArgs& a);

// --- density ----------------------------------------------------------------------------------------------
/// Adds weights[edge] to img[iy·size + ix] for every point inside [0, size)² (ix, iy = floor); points
/// outside are dropped. Returns the box of the pixels hit. `img` must be size² zeros.
Box splat(const Points& p, const std::vector<std::uint32_t>& weights, int size,
          std::vector<std::uint32_t>& img);
/// The region of the density image that advection can read: `box` grown by 2 px, clipped to the image.
Box read_region(const Box& box, int size);
/// Separable convolution of `img` with kernel_taps(radius), zero outside the image, exact (mod 2^64), on
/// read_region(box) only: rows[y][x] = Σ_k K[k]·img[y][x+k−R] for y in box rows (other rows are zero),
/// then dens[y][x] = float(Σ_k K[k]·rows[y+k−R][x]) (the exact sum rounded to nearest: half the memory
/// for advection to read, and float resolves the gradient as well as the original's float texture).
/// Values outside the region are not written. `rows` and `dens` must hold size² values.
void convolve(const std::vector<std::uint32_t>& img, int size, const Box& box, int radius,
              std::vector<std::uint64_t>& rows, std::vector<float>& dens);
/// ρ at (sx, sy) px, bilinear between texel centres (texel (i, j) is the value at (i + 0.5, j + 0.5)),
/// indices clamped to the image (the original's CLAMP_TO_EDGE texture).
double sample_density(const std::vector<float>& dens, int size, double sx, double sy);
/// Moves every point with z > 0 inside the image by step·z·g/|g|, g the central difference of ρ over ±1 px
/// (no move where |g|² < 1e−4). `step` = eps · h_i.
void advect(Points& p, const std::vector<float>& dens, int size, double step);
/// `passes` Laplacian passes: p' = (1 − λz)·p + λz·mean(p[j−L .. j+L] clipped to the polyline).
void smooth(Points& p, int window, double lambda, int passes);

/// The whole loop on `pts` (already with the original polylines as points): iterations × (resample,
/// splat, convolve, advect, smooth), timing each phase into the given slots (ms), with progress and
/// cancellation between iterations.
struct LoopTimes {
  double resample_ms = 0, splat_ms = 0, convolve_ms = 0, advect_ms = 0, smooth_ms = 0;
};
Points run_loop_ref(Points pts, const BundleParams& params, const std::vector<std::uint32_t>& weights,
                    LoopTimes& times, const ProgressFn& progress, const CancelToken* cancel);

/// The fixed-kernel loop of streaming bundling (streaming.hpp): `iterations` × (splat, convolve with
/// `radius`, advect by `step`, smooth), with no resampling and no kernel decay, on `pts` in place.
struct FixedArgs {
  int size = 512;       ///< density image edge, px
  int radius = 16;      ///< kernel_radius(h) of the fixed kernel
  double step = 0.8;    ///< eps · h, px
  int window = 1;       ///< smooth_window()
  double lambda = 0.2;  ///< smoothing strength
  int passes = 1;       ///< smoothing passes
  int iterations = 2;   ///< iterations of this call
};
void run_fixed_ref(Points& pts, const std::vector<std::uint32_t>& weights, const FixedArgs& a,
                   LoopTimes& times);

}  // namespace trailscope::bundling::detail
