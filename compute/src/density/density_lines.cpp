// density_lines: segment preparation (exact integer clipping of each segment's pixel walk to the canvas)
// and the dispatch between the OpenCL kernel and the reference (density_lines_ref.cpp).
//
// Why `auto` never picks PoCL's CPU device. Measured on the 2-core build machine, idle (PoCL 3.1,
// Europe SO6 day without gap limit, median of 25 runs, density_lines alone on the same prepared segments):
//   canvas                      segments  pixel visits   count: ref / PoCL     altitude: ref / PoCL
//   tile 3/4/2, 256²              78,106     1,027,275     2.6 /  3.9 ms        2.8 /  10.4 ms
//   tile 4/8/5, 256²              65,625     1,469,235     3.1 /  7.5 ms        3.6 /  15.3 ms
//   tile 4/8/5, 512²              70,314     2,933,608     4.5 / 13.7 ms        6.4 /  29.5 ms
//   Europe at z=4, 627×625       111,467     2,633,703     4.3 /  9.1 ms        6.2 /  24.6 ms
//   Europe, 2048×2043            124,552     8,594,587    23.5 / 35.9 ms       80.9 / 115.7 ms
// The kernel's scatter (one work-item per segment, an atomic per pixel) is 1.5–3× slower than the
// reference for counts and 1.4–4× for values (64-bit atomics): on a CPU, OpenCL atomics are locked
// read-modify-writes on shared cache lines, while the reference adds into a private grid per thread and
// sums the grids. A GPU has native atomics and the bandwidth to gain on large inputs, so `auto`
// considers GPUs and accelerators only, from kAutoOpenClMinSegments segments (a threshold chosen
// without a GPU measurement yet: revisit it with tests/bench on one).
#include "trailscope/trails/point_filter.hpp"
#include "trailscope/trails/time_index.hpp"
#include "trailscope/density/density_lines.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "ocl/dispatch.hpp"
#include "density/density_lines_ocl.hpp"
#include "density/density_lines_walk.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/geo/web_mercator.hpp"

namespace trailscope::density {
namespace {

using i128 = __int128;
constexpr std::int64_t kWorld = std::int64_t{1} << 32;
constexpr std::int64_t kHalfWorld = std::int64_t{1} << 31;

constexpr std::int64_t floor_div(std::int64_t a, std::int64_t b) {  // b > 0
  const std::int64_t q = a / b;
  return (a % b != 0 && a < 0) ? q - 1 : q;
}
constexpr i128 floor_div(i128 a, i128 b) {  // b > 0
  const i128 q = a / b;
  return (a % b != 0 && a < 0) ? q - 1 : q;
}
constexpr i128 ceil_div(i128 a, i128 b) {  // b > 0
  const i128 q = a / b;
  return (a % b != 0 && a > 0) ? q + 1 : q;
}
constexpr int sign(std::int64_t v) {
  return (v > 0) - (v < 0);
}

// An event time along the segment, t = num/den (den > 0), with the order of events at equal t: flag 0
// for a crossing in the positive direction (it happens AT t: the boundary belongs to the next pixel),
// 1 for the negative direction (it happens just AFTER t), -1 for "before everything" (t = 0, no event).
struct Key {
  i128 num = 0, den = 1;
  int flag = -1;
};
bool less(const Key& a, const Key& b) {
  const i128 l = a.num * b.den, r = b.num * a.den;
  return l < r || (l == r && a.flag < b.flag);
}

// Pixel index along one axis after every event with key <= k (see density_lines.hpp: the half-open rule).
std::int64_t cell_at(std::int64_t a, std::int64_t delta, int s, std::int64_t p, const Key& k) {
  if (s == 0) return floor_div(a, p);
  const i128 pos = i128{a} * k.den + i128{delta} * k.num;  // position · den
  const i128 size = i128{p} * k.den;
  if (s < 0 && k.flag == 1) return static_cast<std::int64_t>(ceil_div(pos, size) - 1);
  return static_cast<std::int64_t>(floor_div(pos, size));
}

// The pixel size, with a shift for the usual power-of-two case: a 64-bit division costs tens of cycles
// and four of them per segment were most of the preparation time of a tile.
struct Grid {
  std::int64_t p;
  int shift;  // log2(p), or -1
  explicit Grid(std::int64_t units)
      : p(units),
        shift(std::has_single_bit(static_cast<std::uint64_t>(units))
                  ? std::countr_zero(static_cast<std::uint64_t>(units))
                  : -1) {}
  std::int64_t cell(std::int64_t a) const { return shift >= 0 ? a >> shift : floor_div(a, p); }  // >> floors
};

// Stores the walk of segment a → b (canvas-relative units) from its first pixel inside the canvas.
void prepare_one(LineSegments& out, const Grid& grid, std::int64_t ax, std::int64_t ay, std::int64_t bx,
                 std::int64_t by, bool skip_first, std::int32_t value, bool has_value) {
  const int w = out.width, h = out.height;
  const std::int64_t p = grid.p;
  const std::int64_t cax = grid.cell(ax), cay = grid.cell(ay);
  const std::int64_t cbx = grid.cell(bx), cby = grid.cell(by);
  if (std::max(cax, cbx) < 0 || std::min(cax, cbx) > w - 1 || std::max(cay, cby) < 0 ||
      std::min(cay, cby) > h - 1)
    return;
  // A continuing segment within one pixel adds nothing (its only pixel is the one it leaves out). Dense
  // tracks at low zoom are mostly such segments, so they are not stored at all.
  if (skip_first && cax == cbx && cay == cby) return;
  const std::int64_t dx = bx - ax, dy = by - ay;
  const int sx = sign(dx), sy = sign(dy);
  const std::int64_t adx = dx < 0 ? -dx : dx, ady = dy < 0 ? -dy : dy;

  std::int64_t i = cax, j = cay;
  if (cax < 0 || cax > w - 1 || cay < 0 || cay > h - 1) {
    // The first endpoint is outside: find the first pixel of the walk inside. Along each axis the pixel
    // index enters the canvas range at one event (or is inside from t = 0); the walk is inside from the
    // later of the two events on, if the other index has not left its range by then (the walk is
    // monotone in both axes, so it cannot come back).
    skip_first = false;  // the shared first pixel is outside the canvas
    Key kx, ky;
    if (cax < 0)
      kx = Key{-i128{ax}, i128{dx}, 0};  // sx > 0: enter column 0 at x = 0
    else if (cax > w - 1)
      kx = Key{i128{ax} - i128{w} * p, i128{adx}, 1};  // sx < 0: enter column w-1 after x = w·p
    if (cay < 0)
      ky = Key{-i128{ay}, i128{dy}, 0};
    else if (cay > h - 1)
      ky = Key{i128{ay} - i128{h} * p, i128{ady}, 1};
    const Key k = less(kx, ky) ? ky : kx;
    i = cell_at(ax, dx, sx, p, k);
    j = cell_at(ay, dy, sy, p, k);
    if (i < 0 || i > w - 1 || j < 0 || j > h - 1) return;  // passes by the canvas corner
  }
  // Decision variable at pixel (i, j): with ex, ey the distances (units) from the first endpoint to the
  // next vertical / horizontal pixel edge in the walk direction, the edges are reached at t = ex/|dx| and
  // ey/|dy|; d = ex·|dy| − ey·|dx| has the sign of their difference. Within the walk |d| <= p·max(|dx|,
  // |dy|) < 2^60, so the device works in int64 from here on.
  const i128 ex = sx > 0 ? i128{i + 1} * p - ax : (sx < 0 ? i128{ax} - i128{i} * p : 0);
  const i128 ey = sy > 0 ? i128{j + 1} * p - ay : (sy < 0 ? i128{ay} - i128{j} * p : 0);
  const i128 d = ex * ady - ey * adx;
  constexpr i128 kLimit = i128{1} << 62;
  if (d > kLimit || d < -kLimit || ex < 0 || ey < 0)
    throw Error(Error::Kind::internal, "", "density_lines: walk state out of range (a bug)");
  out.walk.push_back(static_cast<std::int64_t>(d));
  out.walk.push_back(p * ady);
  out.walk.push_back(p * adx);
  out.cells.push_back(static_cast<std::int32_t>(i));
  out.cells.push_back(static_cast<std::int32_t>(j));
  out.cells.push_back(static_cast<std::int32_t>(std::clamp<std::int64_t>(cbx, -1, w)));
  out.cells.push_back(static_cast<std::int32_t>(std::clamp<std::int64_t>(cby, -1, h)));
  out.cells.push_back((sx + 1) | ((sy + 1) << 2) | (skip_first ? 16 : 0) | (has_value ? 32 : 0));
  out.cells.push_back(value);
}

// The canvas's rows as latitudes, so that a flight's (float) latitude extents are tested against them
// without projecting two latitudes per flight: lat_to_merc_y's tan and asinh were a seventh of a cold tile
// over a dense hour. The answer is the projection's: a flight whose extents lie within kBandDeg of a
// boundary (several y units anywhere; the projection's rounding is about one) is decided by projecting.
class RowTest {
 public:
  /// Rows [y_top, y_bottom] in units (either may lie outside the world).
  RowTest(std::int64_t y_top, std::int64_t y_bottom) : y_top_(y_top), y_bottom_(y_bottom) {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    // y_top <= 0: no latitude projects north of it; beyond the world's last row every latitude does.
    north_ = y_top <= 0 ? kInf : y_top > kLastRow ? -kInf : geo::merc_y_to_lat(static_cast<double>(y_top));
    south_ = y_bottom >= kLastRow ? -kInf
             : y_bottom < 0       ? kInf
                                  : geo::merc_y_to_lat(static_cast<double>(y_bottom));
  }
  /// No latitude of [lat_min, lat_max] projects into the rows: lat_to_merc_y(lat_min) < y_top or
  /// lat_to_merc_y(lat_max) > y_bottom.
  bool misses(float lat_min, float lat_max) const {
    const double lo = lat_min, hi = lat_max;
    if (lo < north_ - kBandDeg && hi > south_ + kBandDeg) return false;
    if (lo > north_ + kBandDeg || hi < south_ - kBandDeg) return true;
    return geo::lat_to_merc_y(lo) < y_top_ || geo::lat_to_merc_y(hi) > y_bottom_;  // also NaN extents
  }

 private:
  static constexpr double kBandDeg = 1e-6;  // a y unit is 8.4e-8° at the equator, less towards the poles
  static constexpr std::int64_t kLastRow = 0xFFFFFFFF;
  std::int64_t y_top_, y_bottom_;
  double north_, south_;  // latitudes of y_top and y_bottom (±infinity: every or no latitude beyond)
};

// std::lower_bound over a flight's time-sorted points with a conditional move instead of a branch per
// step: the branch is unpredictable, and these two searches per flight were a third of preparing a tile
// over a dense hour. (What remains is waiting for memory: starting from the guess an even sampling rate
// gives, which touches fewer cache lines, measured no faster.)
std::uint32_t lower_bound_time(const std::vector<double>& t, std::uint32_t begin, std::uint32_t end,
                               double x) {
  if (begin == end) return begin;
  const double* base = t.data() + begin;
  std::uint32_t n = end - begin;
  while (n > 1) {  // the answer lies in [base, base + n]
    const std::uint32_t half = n / 2;
    base += base[half] < x ? half : 0;
    n -= half;
  }
  return static_cast<std::uint32_t>(base - t.data()) + (*base < x ? 1 : 0);
}

}  // namespace

std::int32_t to_fixed(double v) {
  const double f = std::nearbyint(v * kValueScale);
  constexpr double lo = std::numeric_limits<std::int32_t>::min(),
                   hi = std::numeric_limits<std::int32_t>::max();
  return static_cast<std::int32_t>(std::clamp(f, lo, hi));
}

double segment_value(float a, float b) {
  const bool ka = !std::isnan(a), kb = !std::isnan(b);
  if (ka && kb) return 0.5 * (static_cast<double>(a) + static_cast<double>(b));
  if (ka) return a;
  if (kb) return b;
  return std::numeric_limits<double>::quiet_NaN();
}

DensityValue parse_density_value(std::string_view text, const std::string& param) {
  if (text == "count") return DensityValue::count;
  if (text == "altitude") return DensityValue::altitude;
  if (text == "speed") return DensityValue::speed;
  throw invalid_argument(
      param, "unknown density value '" + std::string(text) + "' (expected count, altitude or speed)");
}

const char* to_string(DensityValue v) noexcept {
  switch (v) {
    case DensityValue::count:
      return "count";
    case DensityValue::altitude:
      return "altitude";
    case DensityValue::speed:
      return "speed";
  }
  return "count";
}

const char* to_string(ComputePath p) noexcept {
  return p == ComputePath::opencl ? "opencl" : "cpu";
}

LineSegments LineSegments::for_canvas(const Canvas& canvas, bool with_value) {
  LineSegments s;
  s.width = canvas.width();
  s.height = canvas.height();
  s.with_value = with_value;
  return s;
}

void append_segment(LineSegments& out, const Canvas& canvas, MercPoint a, MercPoint b, bool continues_run,
                    double value) {
  // The short way round: unwrap b next to a.
  const std::int64_t dx = b.x - a.x;
  if (dx > kHalfWorld)
    b.x -= kWorld;
  else if (dx < -kHalfWorld)
    b.x += kWorld;
  const std::int64_t min_x = std::min(a.x, b.x), max_x = std::max(a.x, b.x);
  const std::int64_t ox = canvas.origin_x(), oy = canvas.origin_y(), end_x = canvas.end_x();
  if (std::max(a.y, b.y) < oy || std::min(a.y, b.y) >= canvas.end_y()) return;
  // Every copy shifted by k worlds whose x range meets [ox, end_x).
  const std::int64_t k_lo = -floor_div(max_x - ox, kWorld);  // = ceil((ox - max_x) / world)
  const std::int64_t k_hi = floor_div(end_x - 1 - min_x, kWorld);
  const bool has_value = out.with_value && !std::isnan(value);
  const std::int32_t fixed = has_value ? to_fixed(value) : 0;
  const Grid grid(canvas.pixel_units());
  for (std::int64_t k = k_lo; k <= k_hi; ++k) {
    const std::int64_t shift = k * kWorld - ox;
    prepare_one(out, grid, a.x + shift, a.y - oy, b.x + shift, b.y - oy, continues_run, fixed, has_value);
  }
}

namespace {

// The segments of a TrailSet under a query for one canvas, prepared a chunk of flights at a time (fixed
// chunks, so that the segment order does not depend on the thread count): prepare_line_segments()
// concatenates the chunks, aggregate_lines() walks each chunk as soon as it is prepared.
class SegmentPreparer {
 public:
  static constexpr std::size_t kChunk = 256;  // flights

  SegmentPreparer(const TrailSet& trails, const Query& query, const Canvas& canvas, DensityValue value,
                  double max_gap_seconds)
      : trails_(trails),
        query_(query),
        canvas_(canvas),
        with_value_(value != DensityValue::count),
        max_gap_(max_gap_seconds),
        flights_(trails.flights()),
        pts_(trails.points()),
        mx_(trails.merc_x()),
        my_(trails.merc_y()),
        values_(value == DensityValue::altitude ? pts_.alt.data()
                : value == DensityValue::speed  ? pts_.speed.data()
                                                : nullptr),
        p_(canvas.pixel_units()),
        // one pixel of slack for the float extents' rounding
        cx0_(canvas.origin_x() - p_),
        cx1_(canvas.end_x() + p_),
        rows_(canvas.origin_y() - p_, canvas.end_y() + p_),
        matches_(query),
        every_point_(matches_.every_point()),
        // When the canvas lies within the world in x, a segment that does not cross 180° has no wrapped
        // copy on it, and the common case goes straight to prepare_one.
        canvas_in_world_(canvas.origin_x() >= 0 && canvas.end_x() <= kWorld),
        grid_(p_),
        ox_(canvas.origin_x()),
        oy_(canvas.origin_y()),
        last_col_(canvas.width() - 1),
        last_row_(canvas.height() - 1) {
    if (!(max_gap_seconds > 0))
      throw invalid_argument("max_gap", "the largest time gap of a drawn segment must be > 0 s");
    // A time window with the set's time index (trails/time_index.hpp): only the flights that may meet
    // it, and of each only its points from the first inside it (the points before fail the window, so no
    // segment before it is drawn and the run starts there, exactly as a walk from the flight's start
    // gives).
    const TimeIndex& ix = trails.time_index();
    windowed_ = ix.valid() && (query.t0 || query.t1);
    constexpr double kInf = std::numeric_limits<double>::infinity();
    t0_ = query.t0.value_or(-kInf), t1_ = query.t1.value_or(kInf);
    const auto range =
        windowed_ ? ix.flight_range(t0_, t1_) : std::pair<std::size_t, std::size_t>{0, flights_.size()};
    fb_ = range.first, fe_ = range.second;
  }

  std::size_t chunks() const { return (fe_ - fb_ + kChunk - 1) / kChunk; }
  /// Large enough to prepare in parallel.
  bool parallel() const { return chunks() > 1 && trails_.num_points() >= 20000; }
  LineSegments empty() const { return LineSegments::for_canvas(canvas_, with_value_); }

  /// Appends the segments of chunk `c`'s flights to `out`.
  void prepare_chunk(std::size_t c, LineSegments& out) const {
    const std::size_t end = std::min(fe_, fb_ + (c + 1) * kChunk);
    for (std::size_t f = fb_ + c * kChunk; f < end; ++f) draw_flight(flights_[f], out);
  }

 private:
  // The flight's extents as a zone map: a flight whose box (or a copy of it one world east or west)
  // misses the canvas has no segment on it. Extents across 180° say nothing about x.
  bool may_meet(const Flight& f) const {
    if (rows_.misses(f.lat_min, f.lat_max)) return false;
    if (f.crosses_antimeridian || f.lon_min > f.lon_max) return true;
    const std::int64_t x0 = geo::lon_to_merc_x(f.lon_min), x1 = geo::lon_to_merc_x(f.lon_max);
    for (std::int64_t k = -1; k <= 1; ++k)
      if (x1 + k * kWorld >= cx0_ && x0 + k * kWorld <= cx1_) return true;
    return false;
  }

  void draw_flight(const Flight& f, LineSegments& out) const {
    if (f.size() < 2 || !query_.may_match(f) || !may_meet(f)) return;
    std::uint32_t first = f.begin, last = f.end;
    if (windowed_) {
      if (t0_ > f.t_min) first = lower_bound_time(pts_.t, f.begin, f.end, t0_);
      if (t1_ <= f.t_max) last = lower_bound_time(pts_.t, first, f.end, t1_);
      if (last - first < 2) return;
    }
    // Without time, altitude, ground or bbox filters every point matches: no per-point test.
    bool prev_ok = every_point_ || matches_(pts_, first);
    bool prev_drawn = false;
    for (std::uint32_t i = first + 1; i < last; ++i) {
      const bool ok = every_point_ || matches_(pts_, i);
      const bool draw = ok && prev_ok && pts_.t[i] - pts_.t[i - 1] <= max_gap_;
      if (draw) {
        const std::int64_t ax = std::int64_t{mx_[i - 1]} - ox_, ay = std::int64_t{my_[i - 1]} - oy_;
        const std::int64_t bx = std::int64_t{mx_[i]} - ox_, by = std::int64_t{my_[i]} - oy_;
        if (canvas_in_world_ && bx - ax <= kHalfWorld && ax - bx <= kHalfWorld) {
          const std::int64_t cax = grid_.cell(ax), cbx = grid_.cell(bx), cay = grid_.cell(ay),
                             cby = grid_.cell(by);
          const bool misses = std::max(cax, cbx) < 0 || std::min(cax, cbx) > last_col_ ||
                              std::max(cay, cby) < 0 || std::min(cay, cby) > last_row_;
          const bool adds_nothing = prev_drawn && cax == cbx && cay == cby;
          if (!misses && !adds_nothing) {
            const double v = value_of(i);
            const bool has_value = with_value_ && !std::isnan(v);
            prepare_one(out, grid_, ax, ay, bx, by, prev_drawn, has_value ? to_fixed(v) : 0, has_value);
          }
        } else {
          append_segment(out, canvas_, MercPoint{mx_[i - 1], my_[i - 1]}, MercPoint{mx_[i], my_[i]},
                         prev_drawn, value_of(i));
        }
      }
      prev_drawn = draw;
      prev_ok = ok;
    }
  }

  double value_of(std::uint32_t i) const {  // of the segment ending at point i
    return values_ ? segment_value(values_[i - 1], values_[i]) : std::numeric_limits<double>::quiet_NaN();
  }

  const TrailSet& trails_;
  const Query& query_;
  const Canvas& canvas_;
  bool with_value_;
  double max_gap_;
  const std::vector<Flight>& flights_;
  const PointColumns& pts_;
  const std::vector<std::uint32_t>& mx_;
  const std::vector<std::uint32_t>& my_;
  const float* values_;
  std::int64_t p_, cx0_, cx1_;
  RowTest rows_;
  PointFilter matches_;
  bool every_point_, canvas_in_world_;
  Grid grid_;
  std::int64_t ox_, oy_, last_col_, last_row_;
  bool windowed_ = false;
  double t0_ = 0, t1_ = 0;
  std::size_t fb_ = 0, fe_ = 0;
};

}  // namespace

LineSegments prepare_line_segments(const TrailSet& trails, const Query& query, const Canvas& canvas,
                                   DensityValue value, double max_gap_seconds) {
  const SegmentPreparer prep(trails, query, canvas, value, max_gap_seconds);
  std::vector<LineSegments> parts(prep.chunks(), prep.empty());
  auto run_chunk = [&](std::size_t c) { prep.prepare_chunk(c, parts[c]); };
  if (prep.parallel()) {
    tbb::parallel_for(std::size_t{0}, parts.size(), run_chunk);
  } else {
    for (std::size_t c = 0; c < parts.size(); ++c) run_chunk(c);
  }
  // Concatenated in chunk order: the segment order (and so the result, though integer sums would not
  // care) does not depend on the thread count.
  LineSegments out = prep.empty();
  std::size_t total = 0;
  for (const auto& part : parts) total += part.size();
  out.walk.reserve(3 * total);
  out.cells.reserve(6 * total);
  for (const auto& part : parts) {
    out.walk.insert(out.walk.end(), part.walk.begin(), part.walk.end());
    out.cells.insert(out.cells.end(), part.cells.begin(), part.cells.end());
  }
  return out;
}

Aggregate aggregate_lines(const TrailSet& trails, const Query& query, const Canvas& canvas,
                          DensityValue value, double max_gap_seconds, Backend backend,
                          std::size_t* segments) {
  // Only `auto` asks about the device, and only for a set large enough to give kAutoOpenClMinSegments
  // segments (a segment's copies across 180° aside), so that `cpu` and small sets never initialise the
  // OpenCL runtime, as density_lines() does not.
  const bool on_cpu =
      backend == Backend::cpu ||
      (backend == Backend::auto_ && (trails.num_points() < kAutoOpenClMinSegments || !ocl::device_is_gpu()));
  const std::size_t pixels =
      static_cast<std::size_t>(canvas.width()) * static_cast<std::size_t>(canvas.height());
  if (!on_cpu || pixels > kMaxPrivateGridPixels) {
    const LineSegments s = prepare_line_segments(trails, query, canvas, value, max_gap_seconds);
    if (segments) *segments = s.size();
    return density_lines(s, backend);
  }
  const SegmentPreparer prep(trails, query, canvas, value, max_gap_seconds);
  const bool with_value = value != DensityValue::count;
  Aggregate a = Aggregate::zeros(canvas.width(), canvas.height(), with_value);
  // One chunk: its segments prepared into `scratch` (reused, so that they stay in cache), then walked.
  const auto draw_chunk = [&](std::size_t c, LineSegments& scratch, const SegmentGrids& g) {
    scratch.walk.clear(), scratch.cells.clear();
    prep.prepare_chunk(c, scratch);
    walk_segments(scratch, 0, scratch.size(), g);
    return scratch.size();
  };
  std::size_t n = 0;
  if (!prep.parallel()) {
    LineSegments scratch = prep.empty();
    for (std::size_t c = 0; c < prep.chunks(); ++c) n += draw_chunk(c, scratch, SegmentGrids::of(a));
  } else {
    // Per thread a scratch and a private grid, summed at the end as density_lines_ref sums its own.
    struct Local {
      LineSegments scratch;
      Aggregate grid;
      std::size_t segments = 0;
    };
    tbb::enumerable_thread_specific<Local> local([&] {
      return Local{prep.empty(), Aggregate::zeros(canvas.width(), canvas.height(), with_value), 0};
    });
    tbb::parallel_for(std::size_t{0}, prep.chunks(), [&](std::size_t c) {
      Local& l = local.local();
      l.segments += draw_chunk(c, l.scratch, SegmentGrids::of(l.grid));
    });
    for (const Local& l : local) {
      add_into(a, l.grid);
      n += l.segments;
    }
  }
  ocl::record_path("density_lines", ocl::Path::cpu);
  a.path = ComputePath::cpu;
  if (segments) *segments = n;
  return a;
}

Aggregate Aggregate::zeros(int width, int height, bool with_value) {
  Aggregate a;
  a.width = width;
  a.height = height;
  a.with_value = with_value;
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  a.count.assign(n, 0);
  if (with_value) {
    a.value_sum.assign(n, 0);
    a.value_count.assign(n, 0);
  }
  return a;
}

std::int32_t Aggregate::max_count() const {
  return count.empty() ? 0 : *std::max_element(count.begin(), count.end());
}

std::uint64_t Aggregate::total_count() const {
  std::uint64_t t = 0;
  for (std::int32_t c : count) t += static_cast<std::uint64_t>(c);
  return t;
}

double Aggregate::mean(int x, int y) const {
  const std::size_t idx =
      static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
  if (!with_value || value_count[idx] == 0) return std::numeric_limits<double>::quiet_NaN();
  return static_cast<double>(value_sum[idx]) / kValueScale / value_count[idx];
}

bool Aggregate::same_numbers(const Aggregate& o) const {
  return width == o.width && height == o.height && with_value == o.with_value && count == o.count &&
         value_sum == o.value_sum && value_count == o.value_count;
}

Aggregate density_lines(const LineSegments& segments, Backend backend) {
  if (segments.width < 1 || segments.width > kMaxCanvasPx || segments.height < 1 ||
      segments.height > kMaxCanvasPx)
    throw invalid_argument("segments", "segments were not prepared for a valid canvas");
  if (segments.cells.size() % 6 != 0 || segments.walk.size() != segments.size() * 3)
    throw invalid_argument("segments", "malformed prepared segments (walk/cells sizes disagree)");
  if (segments.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    throw invalid_argument("segments", "more than 2^31 segments in one aggregate");

  Aggregate out;
  // Only `auto` asks whether OpenCL would gain, so that `cpu` never initialises the OpenCL runtime.
  const bool worth =
      backend == Backend::auto_ && segments.size() >= kAutoOpenClMinSegments && ocl::device_is_gpu();
  const ocl::Path path = ocl::dispatch(
      "density_lines", backend, worth, [&] { return ocl::density_lines_ocl(segments, out); },
      [&] { out = density_lines_ref(segments); });
  out.path = path == ocl::Path::opencl ? ComputePath::opencl : ComputePath::cpu;
  return out;
}

}  // namespace trailscope::density
