#pragma once
// Flow maps: the main flows of a traffic (or of an uploaded 2D vector field) as three nested abstraction
// levels of one field (van der Zwan, Telea, Isenberg, "Continuous navigation of nested abstraction
// levels", EuroVis 2012 short papers): 0 = the density, 1 = evenly spaced streamlines of each heading
// sector (streamlines.hpp; Jobard and Lefer 1997), 2 = those streamlines bundled by CUBu (van der Zwan,
// Codreanu, Telea, "CUBu: Universal real-time bundling for large graphs", IEEE TVCG 2016; bundling/
// bundle.hpp, reused as is). Levels in between are blended (render.hpp); between 1 and 2 the geometry
// is CUBu's relaxation toward the streamlines, relaxation = 2 − level.
//
// PIPELINE. traffic_field (field.hpp) or parse_field → per sector, evenly_spaced_streamlines → all
// sectors' lines together → bundling::bundle on the view of the grid (Frame::view of [0, nx] × [0, ny]
// cells onto params.bundle.size pixels). Lines of different sectors are bundled together, so with
// `bundle.directional` (the default here) CUBu's directional bundling keeps opposite flows apart.
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "trailscope/bundling/bundle.hpp"
#include "trailscope/core/backend.hpp"
#include "trailscope/core/progress.hpp"
#include "trailscope/flow/field.hpp"
#include "trailscope/flow/streamlines.hpp"

namespace trailscope::flow {

struct FlowParams {
  FieldParams field;
  StreamlineParams lines;
  bundling::BundleParams bundle = default_bundle_params();
  /// The flow defaults of CUBu: a 512 px image, kernel 24 px, 10 iterations, resampling every 8 px
  /// without jitter, smoothing 0.5, directional (opposite flows repel), ends kept, max_displacement 0.5
  /// (a bundled line stays within half its length of its streamline).
  static bundling::BundleParams default_bundle_params();
  /// Throws invalid_argument naming the first bad parameter (as set() names it).
  void validate() const;
  /// Sets one parameter from text: the field's `grid`, `sectors`, `smooth`, `max_gap`; the streamlines'
  /// (StreamlineParams::set names); or a bundling parameter as `bundle.<name>` (BundleParams::set).
  /// Throws invalid_argument(name) for an unknown name or a bad value, leaving the params unchanged.
  void set(std::string_view name, std::string_view value);
  /// Up-front cost check of a field of nx × ny cells and `sectors` sectors: throws
  /// Error(payload_too_large, `d_sep`) when sectors · lines.max_points(nx, ny) exceeds
  /// limits::kMaxFlowLinePoints.
  void check_cost(int nx, int ny, int sectors) const;
};

struct FlowMap {
  VectorField field;
  bundling::Polylines lines;        ///< all sectors' streamlines, cell coordinates, in flow direction
  std::vector<int> sector;          ///< per line, its sector
  std::vector<float> traffic;       ///< per point of `lines`, the field's w there
  std::vector<float> line_traffic;  ///< per line, the mean of its points' w (what it is weighted by)
  bundling::Bundled bundled;        ///< the lines bundled (bundle pixels; bundled.frame maps cells ↔ px)
  bool has_bundle = false;          ///< false when there are no lines
  double field_ms = 0, lines_ms = 0, bundle_ms = 0;
  /// The polylines drawn at `level` in cell coordinates: the streamlines at level <= 1, at level in
  /// (1, 2] bundling::relax(bundled, 2 − level, bundle.max_displacement) mapped back to cells. Throws
  /// invalid_argument(`level`) outside [0, 2].
  bundling::Polylines lines_at(double level) const;
};

/// The flow map of `field`. Checks the cost first (FlowParams::check_cost). Progress stages "lines",
/// "bundle"; `cancel` is checked between sectors and by the bundling. Throws what validate(), check_cost,
/// evenly_spaced_streamlines and bundling::bundle throw.
FlowMap flow_map(VectorField field, const FlowParams& params, Backend backend = default_backend(),
                 const ProgressFn& progress = {}, const CancelToken* cancel = nullptr);
/// The flow map of the traffic of `trails` under `query` (traffic_field, then the above).
FlowMap flow_map(const TrailSet& trails, const Query& query, const FlowParams& params,
                 Backend backend = default_backend(), const ProgressFn& progress = {},
                 const CancelToken* cancel = nullptr);

/// The lines of `map` at `level` as JSON: {grid: {nx, ny, cell, x0, y0, geographic}, level, sectors,
/// lines: [{sector, heading (compass degrees of the sector's centre, null for an uploaded field),
/// traffic, points: [[lon, lat], ...] (or [x, y] cells for a plain grid), 6 significant digits}],
/// times: {field_ms, lines_ms, bundle_ms}, bundle_path}. Throws as lines_at.
nlohmann::json flow_json(const FlowMap& map, double level);

}  // namespace trailscope::flow
