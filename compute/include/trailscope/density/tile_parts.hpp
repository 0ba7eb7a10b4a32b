#pragma once
// The second half of a density tile for a line-density aggregate counted elsewhere (the shards of a
// database: server/src/store/clickhouse_store.cpp count the pixels each segment touches in SQL), finished
// with the very code aggregate() and DensityRenderer::render_tile() finish theirs with, so the PNG is the
// same bytes.
#include "trailscope/density/aggregate.hpp"
#include "trailscope/density/density_lines.hpp"
#include "trailscope/density/renderer.hpp"
#include "trailscope/density/span.hpp"

namespace trailscope::density {

/// What aggregate() makes of `agg`, the density_lines() aggregate of the grown canvas `work` (the canvas
/// with the kernel's margin): the raster (smoothed when options.kernel_radius > 0, the margin cropped) and
/// the largest inner count. `segments` is left 0 and `path` is agg.path. Throws invalid_argument
/// ("kernel_radius") as aggregate() does.
AggregateResult finish_aggregate(const Aggregate& agg, const Canvas& work, const AggregateOptions& options);

/// The tile of `request` from its aggregate and its level's shared span, shaded and encoded as
/// DensityRenderer::render_tile() does (a transparent PNG when no pixel holds data). `ms` and
/// `span_cached` are left for the caller. Throws what shade() throws.
TileResult shade_tile(const AggregateResult& res, const SpanStats& span, const TileRequest& request);

}  // namespace trailscope::density
