#pragma once
// CUBu bundling (van der Zwan, Codreanu, Telea, "CUBu: Universal Real-Time Bundling for Large Graphs", IEEE
// TVCG 22(12), 2016): kernel-density-estimation edge bundling (KDEEB; Hurter, Ersoy, Telea 2012) run as one
// loop on the OpenCL device, with the extras of CUBu (edge profiles, endpoint clustering, directional
// bundling, relaxation, direction separation).
//
// THE LOOP. The input is fitted into a `size` × `size` pixel image (Frame). For i = 0..iterations−1,
// with h_i = h · ((2/h)^(1/iterations))^i:
//   1. resample every polyline at arc-length step `spl` (samples at m·spl < length), ends kept, interior
//      samples shifted by U[−1,1]·jitter·spl along their segment, clamped to it (seeded hash of seed,
//      iteration, edge and sample: no RNG state, so the result does not depend on threads or device),
//      each with its profile weight z (1024-entry table by arc-length index; 0 at both ends with
//      block_endpoints); with polyline_style only in the first iteration;
//   2. splat the points into a 32-bit integer image (atomic adds: deterministic; points outside the
//      image are dropped) and convolve it with the separable Epanechnikov kernel of radius
//      R = int(h_i/2)·2, taps R² − d² (the original's 1 − (d/R)², times R²), zero outside the image —
//      in exact 64-bit integers by sliding-window moments, O(1) per pixel whatever R, then rounded to
//      float; only the splatted box grown by 2 px (all advection reads) is computed;
//   3. advect each point inside the image by eps · h_i · z · ∇ρ/|∇ρ| (central differences over ±1 px
//      of ρ sampled bilinearly, texel (i, j) holding the value at (i + 0.5, j + 0.5), indices clamped
//      to the image; no move where |∇ρ|² < 1e−4). With `directional`, instead: attraction to the
//      nearby points of other polylines running the same way, repulsion from those running the other
//      way (directional.hpp in compute/src/bundling);
//   4. Laplacian smoothing over a window of int(smooth_kernel · size / spl) points, weighted by z.
// Before the loop, with ms_iterations > 0, endpoint mean-shift clustering; after it, direction
// separation and the per-point figures (relaxation is applied by relax(), on demand).
//
// BACKENDS. bundle() follows the dispatch convention (ocl/dispatch.hpp) for the whole loop: the points
// stay on the device from the first resample to the last smoothing. bundle_ref() is the plain,
// single-threaded C++ reference of the same loop. The two give bit-identical points: integer splats and
// convolution, and geometry in double rounded to float on store, with FP contraction off on both sides.
// The OpenCL path needs cl_khr_fp64; without it bundle() falls back to the reference (or, under
// opencl_strict(), throws Error(backend)). `auto` picks OpenCL on a GPU or accelerator only (on PoCL's
// CPU device the reference is faster; measurements in compute/src/bundling/bundle.cpp).
#include <cstdint>
#include <string>
#include <vector>

#include "trailscope/bundling/params.hpp"
#include "trailscope/bundling/polylines.hpp"
#include "trailscope/core/backend.hpp"
#include "trailscope/core/progress.hpp"

namespace trailscope::bundling {

/// The affine map between source coordinates and bundle pixels: px = (x − x0) · scale + offset_x, and
/// py likewise (or mirrored, with flip_y: py = size − ((y − y0) · scale + offset_y)). Pixels have y down.
struct Frame {
  int size = 512;
  double x0 = 0, y0 = 0, scale = 1, offset_x = 0, offset_y = 0;
  bool flip_y = false;

  /// The frame that fits the bounding box of `lines` into size·(1 − 2·border) pixels, centred (CUBu's
  /// GraphDrawing::normalize). Throws Error(unprocessable, `input`) when the box is empty or degenerate
  /// in both axes.
  static Frame fit(const Polylines& lines, int size, double border, bool flip_y = false);
  /// The frame that maps the box [x0, x1] × [y0, y1] (source units) onto the whole image, the longer
  /// side filling `size` and the other centred: bundling "in the pixel space of a view".
  static Frame view(double x0, double y0, double x1, double y1, int size, bool flip_y = false);
  double to_px_x(double x) const;
  double to_px_y(double y) const;
  double from_px_x(double px) const;
  double from_px_y(double py) const;
  /// Maps every point of `lines` (source → pixels, or back).
  Polylines to_pixels(const Polylines& lines) const;
  Polylines from_pixels(const Polylines& px) const;
};

/// Quality figures reported with every result.
/// Computed on relax(bundled, params.relaxation, params.max_displacement), i.e. on what is drawn.
struct Quality {
  std::uint64_t ink_raw_px = 0;      ///< pixels of the size × size image covered by the input lines
  std::uint64_t ink_bundled_px = 0;  ///< ... by the bundled lines
  double ink_reduction = 0;          ///< 1 − bundled/raw
  double mean_displacement_px = 0;   ///< mean distance of a bundled point from its original point
  double max_displacement_px = 0;
};

/// Time per phase, milliseconds (summed over iterations): wall time on the reference; on OpenCL the device
/// time of each phase's commands (event profiling, so timing adds no synchronisation). total_ms is wall
/// time on both.
struct PhaseTimes {
  double resample_ms = 0, splat_ms = 0, convolve_ms = 0, advect_ms = 0, smooth_ms = 0;
  double endpoints_ms = 0;  ///< endpoint mean-shift clustering
  double post_ms = 0;       ///< relaxation, separation, quality figures
  double total_ms = 0;
};

/// A bundling result, in bundle pixels (Frame::from_pixels maps back to source units).
struct Bundled {
  Frame frame;
  BundleParams params;
  Polylines lines;       ///< the bundled polylines, one per input, direction separation applied (interior
                         ///< points offset by dir_separation·(1−2|t−0.5|)^0.4 along (t_y, −t_x), t the
                         ///< unit tangent in pixels) and relaxation NOT applied (relax() applies
                         ///< params.relaxation or any other)
  Polylines original;    ///< per point of `lines`, the point at the same arc-length fraction of the
                         ///< original polyline (same offsets as `lines`): what relaxation blends toward
  std::vector<float> t;  ///< per point, its arc-length fraction along the bundled polyline
  std::vector<float> displacement;  ///< per point, |bundled − original| / (max_displacement · length)
                                    ///< clamped to [0,1] (the DISPLACEMENT colour mode)
  std::vector<float> length;        ///< per polyline, original arc length, px
  std::vector<float> angle;         ///< per polyline, direction of end − start, radians in (−π, π]
  Quality quality;
  PhaseTimes times;
  std::string path;    ///< "opencl" or "cpu": where the loop ran
  std::string device;  ///< the OpenCL device name, or "" on cpu
};

/// Bundles `input_px` (polylines already in bundle pixels; see Frame) with `params` on `backend`.
/// Reports progress per iteration (stages "endpoints", "bundle", then "post") and checks `cancel`
/// between iterations (throws Error(cancelled)). Throws invalid_argument naming a bad parameter (or
/// `size` when frame.size ≠ params.size, `input` for malformed offsets),
/// Error(payload_too_large, `input`) beyond limits::kMaxBundleEdges polylines, kMaxBundleInputPoints
/// points, or when the resampled points would exceed limits::kMaxBundlePoints (checked before they are
/// allocated), Error(unprocessable, `input`) for an empty input, a polyline of fewer than 2 points or a
/// non-finite point, and Error(backend) under opencl_strict() when OpenCL was chosen and could not run.
Bundled bundle(const Polylines& input_px, const Frame& frame, const BundleParams& params,
               Backend backend = default_backend(), const ProgressFn& progress = {},
               const CancelToken* cancel = nullptr);

/// The single-threaded C++ reference of bundle(): the same result, bit for bit.
Bundled bundle_ref(const Polylines& input_px, const Frame& frame, const BundleParams& params,
                   const ProgressFn& progress = {}, const CancelToken* cancel = nullptr);

/// Relaxation toward the original (CUBu Polyline::interpolate): with l = 1 − relaxation, capped so that
/// l·|p − P| <= max_displacement · length, each point becomes l·p + (1 − l)·P (endpoints included, so
/// that relaxation 1 gives the input even when endpoint clustering moved the ends). Returns the relaxed
/// polylines (bundled.lines is not changed). relaxation 0..1, max_displacement >= 0; throws
/// invalid_argument naming `relaxation` or `max_displacement`, or `bundle` when its arrays disagree.
Polylines relax(const Bundled& bundled, double relaxation, double max_displacement);

/// Ink (pixels of a size × size image touched by the lines, drawn 1 px wide with the exact integer
/// rasteriser of density_lines.hpp, endpoints on a 1/256 px grid). size 1..8192 (invalid_argument).
std::uint64_t ink_pixels(const Polylines& px, int size);

}  // namespace trailscope::bundling
