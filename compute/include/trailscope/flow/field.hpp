#pragma once
// Directional velocity fields of traffic: the first stage of a flow map (flow_map.hpp).
//
// Air traffic is not a single-valued vector field: two airways flown in opposite directions, or two
// crossing flows, cancel when their velocities are averaged per cell. So the field is split by heading:
// one vector field per heading SECTOR (S sectors of 360/S degrees, sector k centred on the compass
// heading k·360/S, sector 0 on north), and a segment only ever adds to the field of its own sector.
//
// GRID. A field lives on a grid of nx × ny square cells. For traffic the grid is laid on 32-bit Web
// Mercator units (geo/web_mercator.hpp): cell (i, j) covers [x0 + i·cell, x0 + (i+1)·cell) ×
// [y0 + j·cell, y0 + (j+1)·cell), rows north → south. Inside the grid, positions are in CELL
// coordinates: x = (mercator_x − x0)/cell to the east, y = (mercator_y − y0)/cell to the south, so
// cell (i, j) is [i, i+1) × [j, j+1) and its centre (i + 0.5, j + 0.5). Directions are in the same
// frame (x east, y south).
//
// WHAT A CELL HOLDS (per sector): w = the length (in cells) of the traffic's track segments inside the
// cell, and (sx, sy) = the sum over those pieces of length · unit direction. So w / 1 cell is about the
// number of flights crossing the cell (a flight crossing straight adds 1, one turning inside adds its
// path length), and (sx, sy)/w is the mean direction, of length 1 when all pieces agree (its length is
// the COHERENCE, 0..1). Sums, not means, are stored, so that smoothing and interpolation weight by
// traffic.
#include <cstdint>
#include <string>
#include <vector>

#include "trailscope/core/limits.hpp"
#include "trailscope/trails/query.hpp"
#include "trailscope/trails/trail_set.hpp"

namespace trailscope::flow {

/// Where a grid lies. `geographic` false: a plain grid (an uploaded field without a bbox), cells of 1
/// unit from (0, 0), no map position.
struct Grid {
  int nx = 0, ny = 0;
  double x0 = 0, y0 = 0;  ///< north-west corner, 32-bit Web Mercator units (x may exceed 2^32 east of 180°)
  double cell = 1;        ///< cell edge, Mercator units (an integer for traffic grids)
  bool geographic = false;
  std::size_t cells() const { return static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny); }
  std::size_t index(int i, int j) const { return static_cast<std::size_t>(j) * nx + i; }
  /// Cell coordinates → longitude/latitude (degrees; longitude wrapped to [−180, 180)). Only for a
  /// geographic grid.
  double lon(double x) const;
  double lat(double y) const;
};

/// One sector's field: per cell (Grid::index), the sums described above.
struct SectorField {
  std::vector<float> sx, sy, w;
};

struct VectorField {
  Grid grid;
  std::vector<SectorField> sectors;  ///< one per heading sector (1 for an uploaded field)
  /// The centre heading of sector k, compass degrees (0 north, 90 east); an uploaded field's single
  /// sector has none (NaN): it holds every direction.
  double sector_heading(int k) const;
  bool by_heading = true;  ///< sectors split by heading (traffic); false for an uploaded field
};

struct FieldParams {
  int grid = 256;   ///< cells along the longer side; 8..kMaxFlowGridCells
  int sectors = 8;  ///< heading sectors; 1..kMaxFlowSectors
  int smooth = 1;   ///< passes of the [1 2 1]/4 filter over each field; 0..8
  double max_gap_seconds = limits::kFlightGapSeconds;  ///< > 0: longer gaps between samples are not flown
  /// Throws invalid_argument naming `grid`, `sectors`, `smooth` or `max_gap`.
  void validate() const;
};

/// The sector of compass heading `deg` (any real; wrapped) among `sectors`: round(deg·S/360) mod S.
int sector_of(double heading_deg, int sectors);

/// The grid of a traffic field: the query's bbox (across 180° when west > east), else the longitude/
/// latitude extent of the flights the query may match (the zone map; the whole world when those cross
/// 180°), in Web Mercator, `grid` cells along the longer side, cells of a whole number of units, the
/// north-west corner on a whole unit. Throws Error(unprocessable, `query`) when no flight may match.
Grid traffic_grid(const TrailSet& trails, const Query& query, int grid);

/// The traffic field of `trails` under `query` on traffic_grid(): every pair of consecutive points of a
/// flight that both pass the query (PointFilter) and are at most max_gap_seconds apart is a straight
/// segment in Web Mercator (x unwrapped: the short way across 180°); its heading picks the sector, and
/// it is cut exactly at the cell edges, each piece adding its length and length · direction to its
/// cell (pieces outside the grid are dropped). Sums are kept in 2^-20-cell fixed point, so the result
/// does not depend on the number of threads. Then `smooth` passes of the separable [1 2 1]/4 filter
/// (zero outside the grid). Throws invalid_argument as FieldParams::validate and what traffic_grid
/// throws.
VectorField traffic_field(const TrailSet& trails, const Query& query, const FieldParams& params);

/// Reads an uploaded 2D vector field (proto/flow_field.md: JSON with width, height, u, v, optional
/// weight and bbox). Throws Error(payload_too_large, `field`) beyond limits::kMaxFlowFieldBytes,
/// Error(unsupported_format, `field`) for text that is not such a JSON object, invalid_argument naming
/// the member (`width`, `height`, `u`, `v`, `weight`, `bbox`, `format`, `version`) when it is missing,
/// of the wrong type or size, or out of range.
VectorField parse_field(const std::string& text);

/// The total traffic per cell (w summed over sectors), row-major.
std::vector<float> total_traffic(const VectorField& field);

}  // namespace trailscope::flow
