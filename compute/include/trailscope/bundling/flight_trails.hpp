#pragma once
// Flight trails as polylines to bundle: the trails of a stored dataset under an airspace time-window
// query, in Web Mercator, split where the data has gaps, so that a bundled map lines up with the basemap.
#include <cstddef>
#include <vector>

#include "trailscope/bundling/bundle.hpp"
#include "trailscope/bundling/polylines.hpp"
#include "trailscope/trails/query.hpp"
#include "trailscope/trails/trail_set.hpp"

namespace trailscope::bundling {

struct FlightTrails {
  Polylines lines;                  ///< 32-bit Web Mercator units (geo/web_mercator.hpp), as doubles
  std::vector<std::size_t> flight;  ///< per polyline, the index of its flight in the TrailSet
  Frame frame;                      ///< the view: the query's bbox (or the data's extent) onto `size` pixels
};

/// The runs of consecutive matching points (PointFilter) of every flight of `trails` under `query`,
/// split where consecutive samples are more than `max_gap_seconds` apart (+infinity: never), runs of
/// fewer than 2 points dropped, and the frame of the view: the query's bbox when it has one, else the
/// extent of the matching points. The points are TrailSet::merc_x/merc_y, x unwrapped along a run (a
/// trail across 180° continues past 2^32 or below 0 instead of jumping); a bbox across 180° spans
/// west .. east + 2^32. Polylines come in TrailSet flight order, each flight's runs in time order.
/// `size` is the bundle image edge (Frame::view; px >= 1). Throws invalid_argument(`max_gap`) unless
/// max_gap_seconds > 0, Error(unprocessable, `query`) when no trail matches, and
/// Error(payload_too_large, `query`) beyond limits::kMaxBundleEdges trails or kMaxBundleInputPoints
/// points.
FlightTrails flight_trails(const TrailSet& trails, const Query& query, int size, double max_gap_seconds);

}  // namespace trailscope::bundling
