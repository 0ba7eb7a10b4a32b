#pragma once
// Density tiles in one call, for the server's tile route and the CLI's `trailscope tile` verb: the whole
// Datashader pipeline (Canvas → aggregate → shade → PNG) with the colour span shared by every tile of a
// zoom (span.hpp) and cached.
//
// THE SHARED SPAN. For a (dataset, query, value, pixel level, kernel radius, gap) the span is computed
// once from a coarse aggregate of the query's whole extent — the data extent, cut to the query's bbox —
// drawn on the pixel grid of the finest level L_s <= L (L = z + log2(size/256)) at which that extent
// fits in kSpanCanvasPx × kSpanCanvasPx pixels. When L_s = L the span is exact (the distribution of the
// very pixels the tiles show). When L_s < L it is an estimate: a pixel at L is 2^(L−L_s) times narrower,
// and the number of lines crossing a square grows with its side, so counts are scaled by 2^(L_s−L) (and,
// without smoothing, floored at 1, since a drawn pixel at L has count >= 1); the KDE radius is scaled by
// the same factor; means are not scaled. Traffic converging on a point (an airport) does not thin out
// with zoom, so above L_s such pixels exceed the estimated span and take the top colour — as they would
// near the top of an exact eq_hist anyway. Either way every tile of the level gets the same span, which
// is what keeps neighbouring tiles seamless. The span is computed on the request's backend, or from a
// coarse aggregate a store counts where its rows are (span_for with a CoarseAggregateFn: the same plan,
// finishing and cache).
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "trailscope/density/aggregate.hpp"
#include "trailscope/density/legend.hpp"
#include "trailscope/density/png.hpp"
#include "trailscope/density/shade.hpp"
#include "trailscope/density/span.hpp"
#include "trailscope/geo/tile_id.hpp"

namespace trailscope::density {

/// Largest edge (pixels) of the coarse canvas a span is estimated from.
inline constexpr int kSpanCanvasPx = 1024;

struct TileRequest {
  geo::TileId tile;                   ///< z in limits::kMinZoom..kMaxZoom, x and y in 0..2^z−1
  int size = limits::kTileSizeSmall;  ///< 256 or 512 pixels
  DensityValue value = DensityValue::count;
  How how = How::eq_hist;
  std::string cmap = "fire";  ///< colormap.hpp names
  int kernel_radius = 0;      ///< KDE radius, pixels, 0..limits::kMaxKernelRadiusPx
  bool alpha_ramp = false;    ///< shade.hpp
  /// Colormap position of the lowest non-empty value (shade.hpp, MINIMUM LEVEL), [0, 1). Unset:
  /// kDefaultCountMinLevel for `count` (faint traffic stays visible on a dark basemap), 0 for `altitude`
  /// and `speed`, whose colours encode a quantity that a floor would misstate.
  std::optional<double> min_level;
  double max_gap_seconds = limits::kFlightGapSeconds;  ///< > 0; +infinity draws every segment
  Backend backend = default_backend();
};

/// Throws invalid_argument naming the first bad field: `z`, `x`, `y`, `size`, `cmap`, `kernel_radius`,
/// `max_gap` or `min_level`.
void validate(const TileRequest& request);

/// The minimum level a tile is shaded with: request.min_level, or its default for the value.
double effective_min_level(const TileRequest& request);

struct TileResult {
  std::string png;              ///< PNG bytes (a fully transparent image when `empty`)
  std::uint64_t max_count = 0;  ///< largest segment count of a pixel of this tile (before smoothing)
  bool empty = true;            ///< no pixel holds data
  std::string path;             ///< "opencl" or "cpu": where density_lines ran
  double ms = 0;                ///< wall time of render_tile, span lookup included
  bool span_cached = false;     ///< the span came from the cache (or another request computing it)
};

struct RenderOptions {
  AggregateOptions aggregate;
  ShadeOptions shade;
};

/// Aggregates and shades an arbitrary canvas (the CLI's bbox rendering). With `span` null the span is
/// the canvas's own data (right for a single image, wrong for tiles: use DensityRenderer). Throws what
/// aggregate() and shade() throw.
Image render_canvas(const TrailSet& trails, const Query& query, const Canvas& canvas,
                    const RenderOptions& options, const SpanStats* span = nullptr);

/// The shared span of one pixel level (see THE SHARED SPAN), computed without caching.
/// `tile_size` is 256 or 512; z and kernel_radius are validated as in TileRequest.
SpanStats estimate_span(const TrailSet& trails, const Query& query, DensityValue value, int z, int tile_size,
                        int kernel_radius, double max_gap_seconds, Backend backend);

/// The coarse aggregate of a span counted elsewhere (a database's shards: server/src/store/
/// clickhouse_store.cpp): given `work`, the coarse canvas grown by the kernel's margin exactly as
/// aggregate() grows a canvas, and the request's value and gap, the density_lines() Aggregate of the
/// query's segments on it (work.width() x work.height(), values when `value` is not count). What it throws
/// propagates (and is not cached).
using CoarseAggregateFn =
    std::function<Aggregate(const Canvas& work, DensityValue value, double max_gap_seconds)>;

/// Renders tiles and owns the span caches (LRU, thread-safe; concurrent requests for a span being
/// computed wait for that computation instead of repeating it; failures are not cached). Two levels:
/// the span of each (dataset, query, value, zoom, size, kernel, gap), and beneath it the unscaled span of
/// each coarse aggregate, which the zooms above L_s share (they differ only by the scale factor), so
/// zooming in costs one coarse aggregate per query rather than one per zoom. One instance per server.
class DensityRenderer {
 public:
  explicit DensityRenderer(std::size_t max_cached_spans = 512);
  ~DensityRenderer();
  DensityRenderer(const DensityRenderer&) = delete;
  DensityRenderer& operator=(const DensityRenderer&) = delete;

  /// Validates `request` (see validate()), then renders its tile of `trails` under `query`.
  /// `dataset_key` must change whenever the TrailSet's content does (it keys the span cache).
  /// Throws invalid_argument naming the bad parameter, or Error(Kind::backend) under opencl_strict().
  TileResult render_tile(const TrailSet& trails, const std::string& dataset_key, const Query& query,
                         const TileRequest& request);

  /// The cached span for a request's level (computing it when needed); `cached` tells which.
  /// Validates as render_tile does.
  std::shared_ptr<const SpanStats> span_for(const TrailSet& trails, const std::string& dataset_key,
                                            const Query& query, const TileRequest& request,
                                            bool* cached = nullptr);
  /// span_for() with the coarse aggregate counted by `coarse` instead of on points: `extent` gives only
  /// the data extent (its flights' extents and whether one crosses 180°, so a set of flights without
  /// points, as a store's outline of a dataset, serves). Same plan, same finishing, same cache entries as
  /// span_for(trails, ...) of the set whose flights `extent` holds: the two overloads share their spans.
  /// Also throws Error(internal) when `coarse` answers an aggregate of another size.
  std::shared_ptr<const SpanStats> span_for(const TrailSet& extent, const std::string& dataset_key,
                                            const Query& query, const TileRequest& request,
                                            const CoarseAggregateFn& coarse, bool* cached = nullptr);

  /// The legend of the tiles `request` describes (legend.hpp): their level's cached span, shaded as
  /// render_tile shades (how, cmap, effective_min_level). request.tile's x and y do not matter. Throws as
  /// span_for() and legend().
  Legend legend(const TrailSet& trails, const std::string& dataset_key, const Query& query,
                const TileRequest& request, int stops);
  /// legend() with the span's coarse aggregate counted by `coarse` (span_for with a CoarseAggregateFn).
  Legend legend(const TrailSet& extent, const std::string& dataset_key, const Query& query,
                const TileRequest& request, int stops, const CoarseAggregateFn& coarse);

  /// Drops every cached span of a dataset (call when it is deleted or replaced).
  void forget_dataset(std::string_view dataset_key);
  /// Spans cached (first level).
  std::size_t cached_spans() const;

 private:
  class Cache;
  std::shared_ptr<const SpanStats> span_of(const TrailSet& trails, const std::string& dataset_key,
                                           const Query& query, const TileRequest& request,
                                           const CoarseAggregateFn* counted, bool* cached);
  Legend legend_of(const TrailSet& trails, const std::string& dataset_key, const Query& query,
                   const TileRequest& request, int stops, const CoarseAggregateFn* counted);
  std::unique_ptr<Cache> spans_, coarse_;
};

}  // namespace trailscope::density
