#pragma once
// Picking on the density map: which flights are drawn under (or near) a point of the screen. The answer
// follows the density tiles exactly: a flight is a candidate through the segments the line-density tile
// draws for the same query (density/density_lines.hpp, WHAT IS DRAWN, with no gap limit, as the tile route
// draws stored flights): the segment between consecutive samples i, i+1 of one flight when both samples
// pass the query's point filter (PointFilter). A lone matching sample draws nothing and is never picked.
//
// DISTANCE. Measured in screen pixels of a Web Mercator map at zoom `zoom` whose world is
// tile_size · 2^zoom pixels wide (MapLibre GL's zoom with tile_size 512; Leaflet's and the XYZ tiles' zoom
// with 256): the Euclidean distance from the point to the closest point of the segment, both in Web
// Mercator, where the tile draws it. A segment with |Δlon| > 180° is drawn the short way across the 180°
// meridian, and the point is compared with every copy of the world, so picking next to the antimeridian
// works from either side. A flight's distance is the least over its drawn segments.
//
// COST. The flights' extents (the zone map) skip every flight that cannot come within the tolerance;
// the rest cost one pass over their points, so a pick costs at most one pass over the window's points —
// the same as the summary — whatever the tolerance and the number of flights answered (both capped by the
// server: kMaxPickTolerancePx, kMaxPickResults in server/src/limits.hpp).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "trailscope/trails/query.hpp"
#include "trailscope/trails/trail_set.hpp"

namespace trailscope {

struct PickRequest {
  /// The point, as Web Mercator unit coordinates: x in [0, 1) from 180°W eastwards, y in [0, 1] from the
  /// north edge (geo::lon_to_unit_x / lat_to_unit_y; a screen pixel (px, py) of a world W pixels wide is
  /// (px / W, py / W)).
  double x = 0, y = 0;
  double zoom = 0;          ///< fractional zoom, limits::kMinZoom..kMaxZoom
  int tile_size = 256;      ///< limits::kTileSizeSmall or kTileSizeLarge: the world is tile_size·2^zoom px
  double tolerance_px = 5;  ///< flights at most this far (pixels, inclusive), > 0 (the server caps it at
                            ///< limits::kMaxPickTolerancePx)
  std::size_t limit = 10;   ///< most flights answered, >= 1 (the server caps it at limits::kMaxPickResults)
};

/// One picked flight, with the closest point of its closest drawn segment.
struct PickHit {
  std::uint32_t id = 0;  ///< flight id, as in the flight list and GET .../flights/{n}
  std::string icao24, callsign;
  double distance_px = 0;   ///< screen pixels at the request's zoom
  double t = 0;             ///< Unix seconds at the closest point (linear in time along the segment)
  double lon = 0, lat = 0;  ///< degrees, the closest point (lon in [-180, 180))
  double alt_m = 0;         ///< metres, linear along the segment; NaN when unknown at either end
};

/// Checks a request; throws invalid_argument naming the field ("zoom", "tile_size", "tolerance", "limit",
/// "x", "y") for one out of range.
void validate_pick(const PickRequest& r);

/// The flights drawn within `r.tolerance_px` of the point under `q`, nearest first (ties by flight id),
/// at most `r.limit`. Throws invalid_argument naming the field ("zoom", "tile_size", "tolerance",
/// "limit", "x", "y") for a request out of range.
std::vector<PickHit> pick_flights(const TrailSet& set, const Query& q, const PickRequest& r);

}  // namespace trailscope
