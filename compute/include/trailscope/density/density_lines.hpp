#pragma once
// Line-density aggregation: the `aggregate` stage of the Datashader pipeline (Canvas → aggregate →
// shade; cf. datashader's Canvas.line with a count/mean reduction), for flight trails. The result is
// numbers per pixel, no colour.
//
// WHAT IS DRAWN. Each segment between consecutive samples i, i+1 of one flight is drawn when both
// samples pass the query (PointFilter) and t[i+1] − t[i] <= max_gap_seconds (default
// limits::kFlightGapSeconds: a longer silence is a gap in coverage, not a straight flight; pass
// +infinity for Douglas-Peucker simplified data such as SO6, whose cruise legs often last longer). A
// segment with |Δlon| > 180° is drawn the short way, across the 180° meridian, and therefore appears on
// both sides of the world (every copy of it shifted by a multiple of 2^32 units that meets the canvas
// is drawn).
//
// WHICH PIXELS (exact, in integers). Endpoints are the samples' 32-bit Mercator positions (TrailSet::
// merc_x/merc_y). Pixel (i, j) is the half-open square [x0 + i·P, x0 + (i+1)·P) × [y0 + j·P, y0 + (j+1)·P)
// of the canvas (origin x0, y0, pixel size P units). A segment touches a pixel iff the closed segment
// intersects that half-open square. The walk that enumerates these pixels (Amanatides & Woo, "A Fast
// Voxel Traversal Algorithm for Ray Tracing", Eurographics 1987, done in exact integer arithmetic)
// visits each of them exactly once, in order from the first endpoint's pixel to the second's; where the
// segment passes exactly through a pixel corner it steps diagonally or through the one side pixel that
// the half-open rule assigns the corner point to. Because the decision depends only on the segment and
// the global pixel grid, never on the canvas window, a trail gives identical pixels on every tile and
// canvas with the same pixel grid: tiles of one zoom have no seams, and the four tiles of zoom z+1 are
// exactly the 512 px rendering of their parent at zoom z cut in four. Between zooms (one parent pixel P
// = its 2×2 child pixels c) a segment touches P iff it touches at least one child, so for segments drawn
// on their own  max(child) <= count(P) <= sum(children). With runs (below) the upper bound still holds
// and the lower one loses the run vertices that lie in P's other children:
//   count(c) − V(P∖c) <= count(P) <= Σ_c count(c),   V(P∖c) = vertices of runs in P but outside c,
// since a run that turns inside P passes a child twice (a hairpin at the finer zoom) but P once. In sum
// over a tile the children hold 1 to 3 times the parent's total (a segment meets at most 3 of a
// square's 4 quadrants), about 2 for long segments (a line is twice as many pixels long at z+1).
//
// SHARED ENDPOINTS. Consecutive drawn segments of one flight (a run) share an endpoint. Its pixel is
// counted once: every segment of a run except the first leaves out its FIRST pixel (the one holding its
// first endpoint), which the previous segment already counted as its last. Consequently a run of
// segments adds exactly 1 to every pixel it passes through once, a segment within one pixel (zero
// length, say) adds nothing unless it starts a run, and a lone matching sample (no drawn segment) draws
// nothing. A pixel's `count` is then the number of segment passes through it, with the vertex pixels of
// a run counted once.
//
// VALUES. `altitude` and `speed` are per-pixel means over the segments that touched the pixel: each
// segment carries the mean of its endpoints' values (the known one when the other is NaN; no value when
// both are NaN), stored as round(v · kValueScale) in int32, summed per pixel in int64 with a count of
// valued segments. Integer sums only: the result does not depend on the order of the additions, the
// number of threads, or the backend.
//
// BACKENDS. density_lines() follows the dispatch convention (validate; OpenCL; else density_lines_ref);
// the OpenCL kernel compute/kernels/density_lines.cl runs one work-item per prepared segment with
// atomic_inc on int32 counts and atom_add on int64 sums, and gives bit-identical aggregates.
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "trailscope/core/backend.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/density/canvas.hpp"
#include "trailscope/trails/query.hpp"
#include "trailscope/trails/trail_set.hpp"

namespace trailscope::density {

/// What a density pixel holds.
enum class DensityValue {
  count,     ///< segment passes through the pixel
  altitude,  ///< mean barometric altitude of those segments, metres
  speed,     ///< mean ground speed of those segments, m/s
};
/// Parses "count" | "altitude" | "speed"; throws invalid_argument(param) otherwise.
DensityValue parse_density_value(std::string_view text, const std::string& param = "value");
const char* to_string(DensityValue v) noexcept;

/// Fixed-point scale of per-segment values (1/256 m or 1/256 m/s).
inline constexpr double kValueScale = 256.0;
/// A segment's value from its endpoints' values (see VALUES): their mean, the known one when the other is
/// NaN, NaN when both are.
double segment_value(float a, float b);
/// A value as the aggregate sums it: round(v · kValueScale) (ties to even), clamped to int32. v not NaN.
std::int32_t to_fixed(double v);

/// Where an op ran.
enum class ComputePath { cpu, opencl };
const char* to_string(ComputePath p) noexcept;

/// A 32-bit Mercator point (units; x may lie outside [0, 2^32) for wrapped copies).
struct MercPoint {
  std::int64_t x = 0, y = 0;
};

/// Segments prepared for one canvas, in the layout the kernel reads: for each segment (clipped to the
/// canvas; segments that miss it, and continuing segments within one pixel, which add nothing, are not
/// stored) the integer state of its walk at the first pixel inside the canvas. Built by
/// prepare_line_segments() or append_segment(); consumed by density_lines().
struct LineSegments {
  int width = 0, height = 0;        ///< of the canvas they were prepared for
  bool with_value = false;          ///< segments carry a value (altitude/speed) to sum
  std::vector<std::int64_t> walk;   ///< 3 per segment: decision d, increment on an x step, on a y step
  std::vector<std::int32_t> cells;  ///< 6 per segment: start i, j; end i, j (clamped to −1..W / −1..H);
                                    ///< flags (bits 0–1: sx+1, 2–3: sy+1, 4: skip first pixel,
                                    ///< 5: has value); value (fixed point)
  std::size_t size() const { return cells.size() / 6; }
  /// Empty, for the given canvas.
  static LineSegments for_canvas(const Canvas& canvas, bool with_value);
};

/// Appends the segment a → b (absolute 32-bit Mercator units, b.x NOT yet unwrapped: if
/// |b.x − a.x| > 2^31 the segment is drawn the short way across 180°) with all its copies that meet the
/// canvas. `continues_run` leaves out the pixel of `a` (see SHARED ENDPOINTS); `value` is the segment's
/// value in natural units, NaN for none (ignored unless out.with_value). Exact: no rounding anywhere.
void append_segment(LineSegments& out, const Canvas& canvas, MercPoint a, MercPoint b, bool continues_run,
                    double value = std::numeric_limits<double>::quiet_NaN());

/// Prepares every drawable segment of `trails` under `query` for `canvas` (see WHAT IS DRAWN), using
/// the flights' extents to skip flights that cannot meet the canvas. `max_gap_seconds` > 0 (NaN or <= 0
/// throws invalid_argument(`max_gap`)). Deterministic; parallel over flights (TBB) for large sets.
LineSegments prepare_line_segments(const TrailSet& trails, const Query& query, const Canvas& canvas,
                                   DensityValue value, double max_gap_seconds = limits::kFlightGapSeconds);

/// Per-pixel integer aggregate, row-major, width × height (margin included).
struct Aggregate {
  int width = 0, height = 0;
  bool with_value = false;
  std::vector<std::int32_t> count;        ///< segment passes per pixel
  std::vector<std::int64_t> value_sum;    ///< Σ round(value · kValueScale) (with_value only)
  std::vector<std::int32_t> value_count;  ///< valued segments per pixel (with_value only)
  ComputePath path = ComputePath::cpu;    ///< which backend produced it

  static Aggregate zeros(int width, int height, bool with_value);
  std::int32_t max_count() const;
  std::uint64_t total_count() const;
  /// Mean value of pixel (x, y) in natural units; NaN when no valued segment touched it.
  double mean(int x, int y) const;
  /// Same numbers (path ignored).
  bool same_numbers(const Aggregate& other) const;
};

/// The op: rasterises prepared segments into an Aggregate on `backend` (cpu, opencl, or auto: OpenCL
/// only on a GPU/accelerator device and for at least kAutoOpenClMinSegments segments — on PoCL's CPU
/// device the kernel's atomic scatter is slower than the TBB reference on the same cores, see
/// density_lines.cpp). Throws Error(Kind::backend) when `opencl` was chosen, could not run and
/// opencl_strict() is set.
Aggregate density_lines(const LineSegments& segments, Backend backend = default_backend());
/// The C++ reference of density_lines (TBB-parallel over segments with per-thread grids for large inputs,
/// summed; integer sums make it deterministic).
Aggregate density_lines_ref(const LineSegments& segments);

/// prepare_line_segments() then density_lines(), with the same numbers on every path. When the walk stays
/// on the CPU (`cpu`, or `auto` without a GPU) and the canvas is small enough for a private grid per
/// thread, in one pass: each chunk of flights is walked as soon as it is prepared, so the segments are
/// never stored whole (gathering them was a tenth of a cold tile over a dense hour). `segments`, when
/// given, receives the number of prepared segments. Throws what those two throw.
Aggregate aggregate_lines(const TrailSet& trails, const Query& query, const Canvas& canvas,
                          DensityValue value, double max_gap_seconds, Backend backend,
                          std::size_t* segments = nullptr);

/// Segments below which `auto` never picks OpenCL, even on a GPU (launch + transfer overhead).
inline constexpr std::size_t kAutoOpenClMinSegments = 50000;

}  // namespace trailscope::density
