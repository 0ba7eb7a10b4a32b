#include "trailscope/density/renderer.hpp"

#include <algorithm>
#include <chrono>
#include <bit>
#include <cmath>
#include <cstdio>
#include <future>

#include "trailscope/core/error.hpp"
#include "trailscope/density/colormap.hpp"
#include "trailscope/geo/web_mercator.hpp"

namespace trailscope::density {
namespace {

using Clock = std::chrono::steady_clock;

void validate_kernel_radius(int r) {
  if (r < 0 || r > limits::kMaxKernelRadiusPx)
    throw invalid_argument("kernel_radius", "kernel radius " + std::to_string(r) + " px is outside 0.." +
                                                std::to_string(limits::kMaxKernelRadiusPx));
}

void validate_size(int size) {
  if (size != limits::kTileSizeSmall && size != limits::kTileSizeLarge)
    throw invalid_argument("size", "tile size " + std::to_string(size) + " px is not " +
                                       std::to_string(limits::kTileSizeSmall) + " or " +
                                       std::to_string(limits::kTileSizeLarge));
}

void validate_gap(double g) {
  if (!(g > 0)) throw invalid_argument("max_gap", "the largest time gap of a drawn segment must be > 0 s");
}

// The query's data extent: the TrailSet's extent cut to the query's bbox; false when empty.
bool query_extent(const TrailSet& trails, const Query& query, geo::LonLatBox& box) {
  if (trails.num_flights() == 0) return false;
  const bool crosses = std::any_of(trails.flights().begin(), trails.flights().end(),
                                   [](const Flight& f) { return f.crosses_antimeridian; });
  box.west = crosses ? -180.0 : trails.lon_min();
  box.east = crosses ? 180.0 : trails.lon_max();
  box.south = trails.lat_min();
  box.north = trails.lat_max();
  if (query.bbox) {
    const BBox& q = *query.bbox;
    box.south = std::max(box.south, q.south);
    box.north = std::min(box.north, q.north);
    if (q.west <= q.east && !crosses) {
      box.west = std::max(box.west, q.west);
      box.east = std::min(box.east, q.east);
    } else {
      box.west = q.west;  // a bbox across 180°, or data across it: keep the query's longitudes
      box.east = q.east;
    }
    if (q.west <= q.east && box.west > box.east) return false;
  }
  box.south = std::max(box.south, -geo::kMaxLatitude);
  box.north = std::min(box.north, geo::kMaxLatitude);
  if (box.south > box.north) return false;
  // A single point, or one meridian / parallel: give the box a hair of extent so it has pixels.
  constexpr double eps = 1e-6;
  if (box.north - box.south < eps)
    box.north = std::min(geo::kMaxLatitude, box.south + eps), box.south = box.north - eps;
  if (box.west <= box.east && box.east - box.west < eps) box.east = box.west + eps;
  return true;
}

// Pixel extent of `box` on the grid of zoom z with tiles of 2^log2_tile px, as Canvas::for_zoom counts it.
bool fits(const geo::LonLatBox& box, int z, int log2_tile, int max_px) {
  constexpr double world = 4294967296.0;
  double span = box.east - box.west;
  if (span <= 0) span += 360.0;
  const double xw = geo::lon_to_unit_x(box.west) * world, xe = xw + span / 360.0 * world;
  const double yn = geo::lat_to_unit_y(box.north) * world, ys = geo::lat_to_unit_y(box.south) * world;
  const double p = std::ldexp(1.0, 32 - z - log2_tile);
  const double w = std::ceil(xe / p) - std::floor(xw / p), h = std::ceil(ys / p) - std::floor(yn / p);
  return w <= max_px && h <= max_px;
}

const std::string& empty_png(int size) {
  auto make = [](int s) {
    Image img;
    img.width = img.height = s;
    img.rgba.assign(static_cast<std::size_t>(s) * s * 4, 0);
    return encode_png(img);
  };
  static const std::string small = make(limits::kTileSizeSmall);
  static const std::string large = make(limits::kTileSizeLarge);
  return size == limits::kTileSizeLarge ? large : small;
}

std::string span_key(const std::string& dataset_key, const Query& query, const TileRequest& r) {
  char gap[32];
  std::snprintf(gap, sizeof gap, "%.17g", r.max_gap_seconds);
  const char sep = '\x1f';
  return dataset_key + sep + query.canonical() + sep + to_string(r.value) + sep + std::to_string(r.tile.z) +
         sep + std::to_string(r.size) + sep + std::to_string(r.kernel_radius) + sep + gap;
}

}  // namespace

void validate(const TileRequest& request) {
  geo::validate_tile(request.tile);
  validate_size(request.size);
  colormap(request.cmap, "cmap");
  validate_kernel_radius(request.kernel_radius);
  validate_gap(request.max_gap_seconds);
}

Image render_canvas(const TrailSet& trails, const Query& query, const Canvas& canvas,
                    const RenderOptions& options, const SpanStats* span) {
  colormap(options.shade.cmap, "cmap");  // fail before the work
  const AggregateResult res = aggregate(trails, query, canvas, options.aggregate);
  SpanStats own;
  if (!span) {
    own = compute_span(res.raster);
    span = &own;
  }
  return shade(res.raster, *span, options.shade);
}

SpanStats estimate_span(const TrailSet& trails, const Query& query, DensityValue value, int z, int tile_size,
                        int kernel_radius, double max_gap_seconds, Backend backend) {
  geo::validate_tile(geo::TileId{z, 0, 0});
  validate_size(tile_size);
  validate_kernel_radius(kernel_radius);
  validate_gap(max_gap_seconds);
  geo::LonLatBox box;
  if (!query_extent(trails, query, box)) return SpanStats{};
  const int log2_tile = std::countr_zero(static_cast<unsigned>(tile_size));
  int zs = z;
  while (zs > 0 && !fits(box, zs, log2_tile, kSpanCanvasPx)) --zs;
  const Canvas coarse = Canvas::for_zoom(box, zs, tile_size);
  const double shrink = std::ldexp(1.0, zs - z);  // pixel width at z over pixel width at zs
  AggregateOptions options;
  options.value = value;
  options.kernel_radius = kernel_radius * shrink >= 0.5 ? kernel_radius * shrink : 0.0;
  options.max_gap_seconds = max_gap_seconds;
  options.backend = backend;
  const AggregateResult res = aggregate(trails, query, coarse, options);
  const bool count = value == DensityValue::count;
  return compute_span(res.raster, count ? shrink : 1.0, count && kernel_radius == 0 ? 1.0 : -1e300);
}

struct DensityRenderer::Slot {
  std::shared_future<std::shared_ptr<const SpanStats>> span;
  Lru::iterator position;
};

DensityRenderer::DensityRenderer(std::size_t max_cached_spans)
    : capacity_(std::max<std::size_t>(1, max_cached_spans)) {}

std::shared_ptr<const SpanStats> DensityRenderer::span_for(const TrailSet& trails,
                                                           const std::string& dataset_key, const Query& query,
                                                           const TileRequest& request, bool* cached) {
  const std::string key = span_key(dataset_key, query, request);
  std::shared_ptr<Slot> slot;
  std::promise<std::shared_ptr<const SpanStats>> promise;
  bool compute = false;
  {
    std::lock_guard lock(mutex_);
    if (auto it = slots_.find(key); it != slots_.end()) {
      slot = it->second;
      lru_.splice(lru_.begin(), lru_, slot->position);
    } else {
      slot = std::make_shared<Slot>();
      slot->span = promise.get_future().share();
      lru_.push_front(key);
      slot->position = lru_.begin();
      slots_.emplace(key, slot);
      compute = true;
      while (slots_.size() > capacity_) {
        slots_.erase(lru_.back());
        lru_.pop_back();
      }
    }
  }
  if (compute) {
    try {
      promise.set_value(std::make_shared<const SpanStats>(
          estimate_span(trails, query, request.value, request.tile.z, request.size, request.kernel_radius,
                        request.max_gap_seconds, request.backend)));
    } catch (...) {
      promise.set_exception(std::current_exception());
      // A failed computation is not cached: the next request tries again.
      std::lock_guard lock(mutex_);
      if (auto it = slots_.find(key); it != slots_.end() && it->second == slot) {
        lru_.erase(slot->position);
        slots_.erase(it);
      }
    }
  }
  if (cached) *cached = !compute;
  return slot->span.get();
}

TileResult DensityRenderer::render_tile(const TrailSet& trails, const std::string& dataset_key,
                                        const Query& query, const TileRequest& request) {
  const auto start = Clock::now();
  validate(request);
  TileResult out;
  const std::shared_ptr<const SpanStats> span =
      span_for(trails, dataset_key, query, request, &out.span_cached);

  AggregateOptions options;
  options.value = request.value;
  options.kernel_radius = request.kernel_radius;
  options.max_gap_seconds = request.max_gap_seconds;
  options.backend = request.backend;
  const AggregateResult res = aggregate(trails, query, Canvas::for_tile(request.tile, request.size), options);
  out.max_count = static_cast<std::uint64_t>(res.max_count);
  out.path = to_string(res.path);
  out.empty = res.raster.valid_count() == 0;
  if (out.empty) {
    out.png = empty_png(request.size);
  } else {
    ShadeOptions shade_options;
    shade_options.how = request.how;
    shade_options.cmap = request.cmap;
    shade_options.alpha_ramp = request.alpha_ramp;
    out.png = encode_png(shade(res.raster, *span, shade_options));
  }
  out.ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  return out;
}

void DensityRenderer::forget_dataset(std::string_view dataset_key) {
  const std::string prefix = std::string(dataset_key) + '\x1f';
  std::lock_guard lock(mutex_);
  for (auto it = lru_.begin(); it != lru_.end();) {
    if (it->compare(0, prefix.size(), prefix) == 0) {
      slots_.erase(*it);
      it = lru_.erase(it);
    } else {
      ++it;
    }
  }
}

std::size_t DensityRenderer::cached_spans() const {
  std::lock_guard lock(mutex_);
  return slots_.size();
}

}  // namespace trailscope::density
