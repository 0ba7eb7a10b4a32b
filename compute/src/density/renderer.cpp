#include "trailscope/density/renderer.hpp"
#include "trailscope/trails/time_index.hpp"

#include <algorithm>
#include <chrono>
#include <bit>
#include <cmath>
#include <future>
#include <list>
#include <mutex>
#include <unordered_map>

#include "trailscope/core/error.hpp"
#include "trailscope/core/text.hpp"
#include "trailscope/density/colormap.hpp"
#include "trailscope/density/tile_parts.hpp"
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
  // The time index knows without a walk over every flight (millions of cache lines in a week).
  const TimeIndex& ix = trails.time_index();
  const bool crosses = ix.valid() ? ix.any_crosses_antimeridian()
                                  : std::any_of(trails.flights().begin(), trails.flights().end(),
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

}  // namespace

void validate(const TileRequest& request) {
  geo::validate_tile(request.tile);
  validate_size(request.size);
  colormap(request.cmap, "cmap");
  validate_kernel_radius(request.kernel_radius);
  validate_gap(request.max_gap_seconds);
  const double level = effective_min_level(request);
  if (!(level >= 0 && level < 1))
    throw invalid_argument("min_level", "min_level must lie in [0, 1), got " + format_double(level));
}

double effective_min_level(const TileRequest& request) {
  if (request.min_level) return *request.min_level;
  return request.value == DensityValue::count ? kDefaultCountMinLevel : 0.0;
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

namespace {

// Where a level's span comes from (THE SHARED SPAN in renderer.hpp).
struct SpanPlan {
  bool empty = true;   // no data under the query
  geo::LonLatBox box;  // the query's data extent
  int zs = 0;          // zoom of the coarse aggregate
  double shrink = 1;   // pixel width at z over pixel width at zs, 2^(zs−z)
  double radius = 0;   // KDE radius at zs (pixels)
};

SpanPlan plan_span(const TrailSet& trails, const Query& query, int z, int tile_size, int kernel_radius) {
  SpanPlan plan;
  if (!query_extent(trails, query, plan.box)) return plan;
  const int log2_tile = std::countr_zero(static_cast<unsigned>(tile_size));
  plan.zs = z;
  while (plan.zs > 0 && !fits(plan.box, plan.zs, log2_tile, kSpanCanvasPx)) --plan.zs;
  plan.shrink = std::ldexp(1.0, plan.zs - z);
  plan.radius = kernel_radius * plan.shrink >= 0.5 ? kernel_radius * plan.shrink : 0.0;
  plan.empty = false;
  return plan;
}

// The unscaled span of the coarse aggregate: aggregated here on `trails`, or, with `counted`, counted
// elsewhere on the same grown canvas and finished as aggregate() finishes its own.
SpanStats coarse_span(const TrailSet& trails, const Query& query, DensityValue value, const SpanPlan& plan,
                      int tile_size, double max_gap_seconds, Backend backend,
                      const CoarseAggregateFn* counted = nullptr) {
  AggregateOptions options;
  options.value = value;
  options.kernel_radius = plan.radius;
  options.max_gap_seconds = max_gap_seconds;
  options.backend = backend;
  const Canvas canvas = Canvas::for_zoom(plan.box, plan.zs, tile_size);
  if (!counted) return compute_span(aggregate(trails, query, canvas, options).raster);
  const int grow = static_cast<int>(std::ceil(options.kernel_radius));
  const Canvas work = grow > 0 ? canvas.with_margin(grow) : canvas;
  const Aggregate agg = (*counted)(work, value, max_gap_seconds);
  if (agg.width != work.width() || agg.height != work.height() ||
      agg.with_value != (value != DensityValue::count))
    throw Error(Error::Kind::internal, "", "span: a coarse aggregate of the wrong size");
  return compute_span(finish_aggregate(agg, work, options).raster);
}

// From the coarse span to the level's: counts scale with the pixel width and, unsmoothed, are >= 1.
SpanStats level_span(const SpanStats& coarse, DensityValue value, const SpanPlan& plan, int kernel_radius) {
  const bool count = value == DensityValue::count;
  return rescale_span(coarse, count ? plan.shrink : 1.0, count && kernel_radius == 0 ? 1.0 : -1e300);
}

}  // namespace

SpanStats estimate_span(const TrailSet& trails, const Query& query, DensityValue value, int z, int tile_size,
                        int kernel_radius, double max_gap_seconds, Backend backend) {
  geo::validate_tile(geo::TileId{z, 0, 0});
  validate_size(tile_size);
  validate_kernel_radius(kernel_radius);
  validate_gap(max_gap_seconds);
  const SpanPlan plan = plan_span(trails, query, z, tile_size, kernel_radius);
  if (plan.empty) return SpanStats{};
  return level_span(coarse_span(trails, query, value, plan, tile_size, max_gap_seconds, backend), value, plan,
                    kernel_radius);
}

// A thread-safe LRU of spans computed on demand. A request for a key whose computation is under way
// waits for it (a shared_future) instead of repeating it; a failed computation is not cached.
class DensityRenderer::Cache {
 public:
  explicit Cache(std::size_t capacity) : capacity_(std::max<std::size_t>(1, capacity)) {}

  template <class Compute>
  std::shared_ptr<const SpanStats> get(const std::string& key, Compute&& compute, bool* cached) {
    std::shared_ptr<Slot> slot;
    std::promise<std::shared_ptr<const SpanStats>> promise;
    bool mine = false;
    {
      std::lock_guard lock(mutex_);
      if (auto it = slots_.find(key); it != slots_.end()) {
        slot = it->second;
        lru_.splice(lru_.begin(), lru_, slot->position);
      } else {
        slot = std::make_shared<Slot>();
        slot->value = promise.get_future().share();
        lru_.push_front(key);
        slot->position = lru_.begin();
        slots_.emplace(key, slot);
        mine = true;
        while (slots_.size() > capacity_) {
          slots_.erase(lru_.back());
          lru_.pop_back();
        }
      }
    }
    if (mine) {
      try {
        promise.set_value(std::make_shared<const SpanStats>(compute()));
      } catch (...) {
        promise.set_exception(std::current_exception());
        std::lock_guard lock(mutex_);
        if (auto it = slots_.find(key); it != slots_.end() && it->second == slot) {
          lru_.erase(slot->position);
          slots_.erase(it);
        }
      }
    }
    if (cached) *cached = !mine;
    return slot->value.get();  // rethrows a failure
  }

  void forget_prefix(const std::string& prefix) {
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

  std::size_t size() const {
    std::lock_guard lock(mutex_);
    return slots_.size();
  }

 private:
  struct Slot {
    std::shared_future<std::shared_ptr<const SpanStats>> value;
    std::list<std::string>::iterator position;
  };
  std::size_t capacity_;
  mutable std::mutex mutex_;
  std::list<std::string> lru_;  // most recent first
  std::unordered_map<std::string, std::shared_ptr<Slot>> slots_;
};

DensityRenderer::DensityRenderer(std::size_t max_cached_spans)
    : spans_(std::make_unique<Cache>(max_cached_spans)), coarse_(std::make_unique<Cache>(max_cached_spans)) {}

DensityRenderer::~DensityRenderer() = default;

std::shared_ptr<const SpanStats> DensityRenderer::span_for(const TrailSet& trails,
                                                           const std::string& dataset_key, const Query& query,
                                                           const TileRequest& request, bool* cached) {
  return span_of(trails, dataset_key, query, request, nullptr, cached);
}

std::shared_ptr<const SpanStats> DensityRenderer::span_for(const TrailSet& extent,
                                                           const std::string& dataset_key, const Query& query,
                                                           const TileRequest& request,
                                                           const CoarseAggregateFn& coarse, bool* cached) {
  return span_of(extent, dataset_key, query, request, &coarse, cached);
}

std::shared_ptr<const SpanStats> DensityRenderer::span_of(const TrailSet& trails,
                                                          const std::string& dataset_key, const Query& query,
                                                          const TileRequest& request,
                                                          const CoarseAggregateFn* counted, bool* cached) {
  validate(request);
  const char sep = '\x1f';
  const std::string base = dataset_key + sep + query.canonical() + sep + to_string(request.value) + sep;
  const std::string gap = format_double(request.max_gap_seconds);
  const std::string key = base + "z" + std::to_string(request.tile.z) + sep + std::to_string(request.size) +
                          sep + std::to_string(request.kernel_radius) + sep + gap;
  return spans_->get(
      key,
      [&] {
        const SpanPlan plan = plan_span(trails, query, request.tile.z, request.size, request.kernel_radius);
        if (plan.empty) return SpanStats{};
        const std::string coarse_key = base + "zs" + std::to_string(plan.zs) + sep +
                                       std::to_string(request.size) + sep + format_double(plan.radius) + sep +
                                       gap;
        const auto coarse = coarse_->get(
            coarse_key,
            [&] {
              return coarse_span(trails, query, request.value, plan, request.size, request.max_gap_seconds,
                                 request.backend, counted);
            },
            nullptr);
        return level_span(*coarse, request.value, plan, request.kernel_radius);
      },
      cached);
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
  const bool cached = out.span_cached;
  out = shade_tile(res, *span, request);
  out.span_cached = cached;
  out.ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  return out;
}

TileResult shade_tile(const AggregateResult& res, const SpanStats& span, const TileRequest& request) {
  TileResult out;
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
    shade_options.min_level = effective_min_level(request);
    out.png = encode_png(shade(res.raster, span, shade_options));
  }
  return out;
}

Legend DensityRenderer::legend(const TrailSet& trails, const std::string& dataset_key, const Query& query,
                               const TileRequest& request, int stops) {
  return legend_of(trails, dataset_key, query, request, stops, nullptr);
}

Legend DensityRenderer::legend(const TrailSet& extent, const std::string& dataset_key, const Query& query,
                               const TileRequest& request, int stops, const CoarseAggregateFn& coarse) {
  return legend_of(extent, dataset_key, query, request, stops, &coarse);
}

Legend DensityRenderer::legend_of(const TrailSet& trails, const std::string& dataset_key, const Query& query,
                                  const TileRequest& request, int stops, const CoarseAggregateFn* counted) {
  validate(request);
  (void)density::legend(SpanStats{}, request.how, request.cmap, effective_min_level(request),
                        stops);  // fail first
  const std::shared_ptr<const SpanStats> span =
      span_of(trails, dataset_key, query, request, counted, nullptr);
  return density::legend(*span, request.how, request.cmap, effective_min_level(request), stops);
}

void DensityRenderer::forget_dataset(std::string_view dataset_key) {
  const std::string prefix = std::string(dataset_key) + '\x1f';
  spans_->forget_prefix(prefix);
  coarse_->forget_prefix(prefix);
}

std::size_t DensityRenderer::cached_spans() const {
  return spans_->size();
}

}  // namespace trailscope::density
