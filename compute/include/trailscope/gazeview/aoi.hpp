#pragma once
// Areas of interest (AOIs) on a stimulus and the usual fixation-based AOI measures (Holmqvist, Nystrom,
// Andersson, Dewhurst, Jarodzka, van de Weijer, "Eye Tracking: A Comprehensive Guide to Methods and
// Measures", Oxford University Press, 2011, ch. 6: dwell time, entry time, transition matrix).
//
// GEOMETRY (stimulus px, origin top-left, y down). A rectangle [x0, x1] x [y0, y1] (closed: a fixation on
// its edge is inside); a polygon of 3 or more vertices (closed by joining the last vertex to the first;
// simple or not, the even-odd rule of OpenCV's cv::pointPolygonTest, boundary inside). All AOIs of one
// query have at most limits::kMaxAoiVertices vertices together (a rectangle counts 4).
//
// WHICH AOI A FIXATION IS IN. Each fixation (at its centroid) belongs to at most one AOI: the FIRST AOI of
// the list that contains it. The list order is the stacking order, first on top, as in the AOI editors
// of eye-tracking software where a smaller AOI drawn over a larger one takes its fixations. So the AOIs'
// fixation counts add up to the fixations inside any AOI, and every fixation has one transition state.
//
// MEASURES, per AOI, over the given fixations (fixations.hpp; grouped by recording, each in time order):
//  - fixations: how many belong to it;
//  - dwell_ms: the sum of their durations (fixation-based dwell time: saccades inside are not counted);
//  - mean_fixation_ms: dwell_ms / fixations (NaN when there are none);
//  - visitors: recordings with at least one of its fixations;
//  - first fixation: per visiting recording, the onset_ms (ms from the recording's first sample) of its
//    first fixation in the AOI ("entry time"); first_fixation_median_ms and _min_ms over the visiting
//    recordings (median of an even count: the mean of the middle two; NaN when no recording visits).
// TRANSITIONS. Within each recording, the fixations inside some AOI in time order; each consecutive pair
// (a, b) adds 1 to counts[aoi(a)][aoi(b)] (row: from, column: to). A fixation outside every AOI is
// skipped: it is not counted and does not break the chain (A, outside, B counts A -> B). Consecutive
// fixations in the same AOI add to the diagonal (refixations). No transition crosses recordings.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trailscope/gazeview/fixations.hpp"

namespace trailscope::gazeview {

struct Aoi {
  std::string name;
  bool is_rect = true;
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< rectangle corners (is_rect)
  std::vector<double> xs, ys;             ///< polygon vertices (!is_rect)
  static Aoi rect(std::string name, double x0, double y0, double x1, double y1);
  static Aoi polygon(std::string name, std::vector<double> xs, std::vector<double> ys);
  /// Whether (x, y) is inside (see GEOMETRY). The AOI must be valid (validate_aois).
  bool contains(double x, double y) const;
};

/// Throws Error(invalid_argument, "aois", ...) naming the AOI (by position and name) when: the list is
/// empty or longer than limits::kMaxGazeAois; a name is empty, longer than 200 bytes or repeated; a
/// coordinate is not finite; a rectangle has x0 >= x1 or y0 >= y1; a polygon has fewer than 3 vertices, or
/// xs and ys of different lengths; a coordinate beyond +-limits::kMaxAoiCoordinatePx; the AOIs have more than
/// limits::kMaxAoiVertices vertices together.
void validate_aois(const std::vector<Aoi>& aois);

struct AoiStats {
  std::string name;
  std::size_t fixations = 0;
  double dwell_ms = 0;
  std::size_t visitors = 0;
  double first_fixation_median_ms = std::numeric_limits<double>::quiet_NaN();
  double first_fixation_min_ms = std::numeric_limits<double>::quiet_NaN();
  double mean_fixation_ms = std::numeric_limits<double>::quiet_NaN();
};

struct AoiReport {
  std::vector<AoiStats> aois;                           ///< in the order given
  std::vector<std::vector<std::uint64_t>> transitions;  ///< [from][to], aois.size() square
  std::size_t fixations = 0;                            ///< fixations given
  std::size_t outside = 0;                              ///< of them, in no AOI
};

/// The measures above. `fixations` must be grouped by recording (all of one recording contiguous) and in
/// time order within each (as view_events returns them). validate_aois() first; work is
/// O(fixations x vertices of all AOIs), bounded by the callers' limit on fixations and kMaxAoiVertices.
AoiReport aoi_statistics(const std::vector<Aoi>& aois, const std::vector<Fixation>& fixations);

/// The AOIs of a JSON array, as the REST body's "aois" and the CLI's --aoi-file hold them:
/// [{"name": "A", "rect": [x0, y0, x1, y1]}, {"name": "B", "polygon": [[x, y], [x, y], [x, y], ...]}].
/// Throws Error(invalid_argument, "aois", ...) naming the AOI for: not an array, an element that is not an
/// object, a missing or non-string name, an unknown key, neither or both of rect and polygon, a rect that is
/// not 4 numbers, a polygon that is not an array of [x, y] number pairs, more than limits::kMaxAoiVertices
/// vertices together (checked before a polygon is read), and then what validate_aois() throws. The array's
/// length is checked against limits::kMaxGazeAois first.
std::vector<Aoi> aois_from_json(const nlohmann::json& j);

/// {"aois": [{"name", "fixations", "dwell_ms", "visitors", "first_fixation_ms": {"median", "min"},
/// "mean_fixation_ms"}], "transitions": {"names": [...], "counts": [[...]]}, "recordings": recordings,
/// "fixations", "outside"}; NaN measures are null.
nlohmann::json to_json(const AoiReport& r, std::size_t recordings);

}  // namespace trailscope::gazeview
