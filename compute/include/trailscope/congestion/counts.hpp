#pragma once
// Congestion counts: how many flights are in an airspace volume, when, and how tangled their traffic
// is. The counts an air-traffic flow manager reads (EUROCONTROL Network Manager, "ATFCM Users Manual"
// and the CHMI reference guide): occupancy counts per counting period, rolling hourly entry counts,
// hotspots against peak and sustained thresholds (the OTMV of the Network Manager), and the traffic
// complexity score of the Performance Review Unit (EUROCONTROL PRU, "Complexity Metrics for ANSP
// Benchmarking Analysis", 2006). Volumes are uploaded sectors or the 20 NM x 20 NM x 3,000 ft grid
// (volumes.hpp). Served by POST /api/v1/congestion and `trailscope congestion`.
//
// THE TRAJECTORY. Each flight of the TrailSet (already split at gaps longer than
// limits::kFlightGapSeconds) moves between consecutive samples a (time ta) and b (time tb > ta) on the
// straight line of (lon, lat, alt) linear in time, exactly as positions.hpp interpolates: longitude the
// short way round (a segment with |Δlon| > 180° crosses 180° and is split there, each part taken in
// [-180, 180]). A segment with an unknown altitude at either end (on the grid: or one beyond ±1,000 km,
// a damaged sample), or with tb == ta, is in no volume;
// a flight is not extrapolated before its first or after its last sample.
//
// INSIDE. A flight's inside set in a volume V is the set of instants at which its trajectory is in V
// (sectors: closed prisms; grid cells: half-open boxes; volumes.hpp). It is computed exactly per segment
// (the times the moving point crosses the polygon's edges, the cell's faces and the altitude bounds,
// each sub-interval classified), so a flight that cuts a corner of a sector between two samples, or
// crosses a whole volume between two samples, is inside for the time it really is; one that only touches
// a boundary point is inside for that instant. Instants are kept exactly: an inside set is a union of
// intervals, each with its ends open or closed.
//
// TIME. The request's window [t0, t1) is cut into counting periods k = 0..K-1, K = ceil((t1-t0)/step):
// period k is [t0 + k·step, min(t0 + k·step + duration, t1)) (the last periods are cut at t1: data at or
// after t1 is never looked at). Entry windows j = 0..J-1, J = ceil((t1-t0)/entry_step), are
// [t0 + j·entry_step, min(t0 + j·entry_step + entry_window, t1)). Complexity hours h = 0..H-1,
// H = ceil((t1-t0)/3600), are [t0 + 3600·h, min(t0 + 3600·(h+1), t1)).
//
// OCCUPANCY of V in period k:
//   - method = interpolated (the default): the number of flights whose inside set in V meets period k;
//   - method = samples: the number of flights with a sample inside V whose time lies in period k (the
//     count a tool that only looks at reported positions gives; it misses a volume crossed between
//     two samples).
// ENTRY COUNT of V in window j: the number of entries into V at a time in window j.
//   - interpolated: every maximal interval of a flight's inside set starts an entry at its start
//     (infimum); a flight whose first sample is inside V enters at that sample's time. A flight that
//     leaves and comes back enters again and counts again (the Network Manager counts entries, not
//     flights; a flight crossing a sector boundary twice loads the controller twice).
//   - samples: a sample inside V whose previous sample of the same flight is not (or that is the
//     flight's first sample) is an entry at its time.
// HOTSPOTS, per volume that has a threshold (its own, else the request's):
//   - peak: every maximal run of consecutive periods with occupancy > peak;
//   - sustained: every maximal run of at least `sustained_steps` consecutive periods with
//     occupancy > sustained.
//   Each with its periods, start (the first period's start), end (the last period's end), the largest
//   occupancy of the run, excess = that largest occupancy - threshold, and the flights counted in any
//   period of the run.
// COMPLEXITY per volume-hour (always on the interpolated trajectory, whatever the method), after the
// PRU (2006): two flights interact while both are inside the same volume.
//   - flight_hours: the summed time flights spend inside the volume during the hour;
//   - interaction_hours: the summed time, over unordered pairs of flights, that both are inside;
//   - horizontal / vertical / speed hours: the part of interaction_hours during which the pair's
//     headings differ by more than heading_deg (20°), their vertical attitudes (climbing: vertical
//     rate > +vrate_fpm, descending: < -vrate_fpm, cruising otherwise; 500 ft/min) differ, or their
//     ground speeds differ by more than speed_kt (35 kt). The PRU report defines the three kinds of
//     interaction; the numbers are defaults, settable per request (ComplexityParams).
//     Heading, ground speed and vertical rate are those of the flight's VISIT of the volume (a maximal
//     interval of its inside set): heading atan2(Δlon·cos φm, Δlat) from the entry point to the exit
//     point (φm their mean latitude; no horizontal interaction when they coincide), speed = the
//     visit's path length in the same local flat metric (1° of latitude = 60 NM) over its duration,
//     vertical rate = Δalt / duration. They are not the samples' reported track, speed and rate;
//     one attitude per visit is what a controller sees of a flight crossing a 20 NM cell (a visit
//     lasts ~2-3 min at cruise speed);
//   - adjusted_density = 60 · interaction_hours / flight_hours (minutes of interaction per flight
//     hour, the PRU's unit); structural_index = (horizontal + vertical + speed hours) /
//     interaction_hours (0 when there is no interaction), in [0, 3];
//     score = adjusted_density · structural_index.
//   The grid's cells are the PRU's; on sectors the same formulas give a per-sector figure.
//
// COST. O(P + C) for P samples of the selected flights and C volume crossings to find the inside sets
// (flights in parallel with TBB), plus O(pieces · flights simultaneously in a volume) for complexity.
// Every size the answer can reach is bounded by a named limit (core/limits.hpp) checked before or while
// counting; nothing partial is returned.
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trailscope/congestion/volumes.hpp"
#include "trailscope/core/progress.hpp"
#include "trailscope/trails/query.hpp"
#include "trailscope/trails/trail_set.hpp"

namespace trailscope::congestion {

enum class Method { interpolated, samples };
/// "interpolated" / "samples".
const char* to_string(Method m) noexcept;
/// Reads "interpolated" or "samples"; throws invalid_argument("method") otherwise.
Method parse_method(const std::string& text);

/// Thresholds of the PRU's three kinds of interaction (EUROCONTROL PRU 2006); defaults, settable.
struct ComplexityParams {
  double heading_deg = 20.0;  ///< horizontal interaction above this heading difference, (0, 180)
  double speed_kt = 35.0;     ///< speed interaction above this ground-speed difference, > 0
  double vrate_fpm = 500.0;   ///< climbing / descending beyond ± this vertical rate, > 0
};

struct CountsRequest {
  /// t0 and t1 are REQUIRED (half-open [t0, t1), span at most limits::kMaxCongestionSpanSeconds).
  /// callsign and icao24 select the flights. On the grid, bbox (default: the whole world) and the
  /// altitude band alt_min / alt_max in metres (default 0 to 60,000 ft) select the extent of cells
  /// (volumes.hpp, GridExtent); they do not cut positions. With sectors, bbox and the altitude band are
  /// refused (a sector has its own). on_ground is refused (the trajectory model is airborne).
  Query query;
  /// The volumes: these sectors, in this order; empty means the grid.
  std::vector<Sector> sectors;
  double step_s = 60;      ///< seconds between counting periods, [1, 3600]
  double duration_s = 60;  ///< length of a counting period, seconds, [60, 3600] (1 to 60 min)
  Method method = Method::interpolated;
  double entry_window_s = 3600;  ///< entry-count window, seconds, [60, 86400]
  double entry_step_s = 1200;    ///< seconds between entry windows, [60, 86400]
  /// Request-level thresholds (flights, finite, >= 0): every grid cell's, and a sector's without its
  /// own. No threshold: no hotspots of that kind.
  std::optional<double> peak, sustained;
  int sustained_steps = 3;  ///< N: a sustained hotspot lasts at least N periods, [1, 10000]
  bool complexity = true;   ///< compute the complexity per volume-hour
  ComplexityParams complexity_params;
};

/// Checks every field as the comments above say, without looking at any data. Throws
/// invalid_argument naming the parameter: "t0" / "t1" (missing, t1 <= t0, span above the limit),
/// "step", "duration", "entry_window", "entry_step", "peak", "sustained", "sustained_steps",
/// "heading_deg", "speed_kt", "vrate_fpm", "bbox" / "alt_min" / "alt_max" (with sectors, or out of
/// range), "on_ground"; Error(payload_too_large, "step") when K, or Error(payload_too_large,
/// "entry_step") when J, exceeds limits::kMaxCongestionSteps, Error(payload_too_large, "bbox") when the grid
/// extent has more than limits::kMaxGridCells cells, Error(payload_too_large, "sectors") above
/// limits::kMaxSectors.
void validate(const CountsRequest& r);

/// Builds the non-volume part of a request from string parameters (a URL query, CLI flags):
/// everything parse_query (query.hpp) reads, plus step, duration, entry_window, entry_step (seconds),
/// method, peak, sustained, sustained_steps, complexity=true|false, heading_deg, speed_kt, vrate_fpm.
/// Unknown keys are ignored. Throws invalid_argument naming the parameter for a malformed value; then
/// validate()s the result (with no sectors: the caller sets them and validates again).
CountsRequest parse_counts_request(const std::map<std::string, std::string>& params);

// --- results ---------------------------------------------------------------------------------------

/// A sparse series: the indices (periods, windows) with a non-zero value, ascending, and the values.
struct Series {
  std::vector<std::uint32_t> index;
  std::vector<std::uint32_t> value;
  /// The dense series of `n` values (zeros where absent).
  std::vector<std::uint32_t> dense(std::size_t n) const;
  std::uint32_t max() const;  ///< largest value, 0 when empty
  std::uint64_t sum() const;
};

struct VolumeResult {
  std::string id;                         ///< sector name, or the grid cell id ("r405c540l11")
  bool is_cell = false;                   ///< a grid cell (bounds below) or a sector (sector index below)
  CellBounds bounds;                      ///< the cell's, or the sector's bounding box and its altitudes
  std::uint32_t sector = 0;               ///< index into CountsRequest::sectors when !is_cell
  std::optional<double> peak, sustained;  ///< thresholds in force (the sector's, else the request's)
  Series occupancy;                       ///< per counting period k
  Series entries;                         ///< per entry window j
};

enum class HotspotKind { peak, sustained };
const char* to_string(HotspotKind k) noexcept;  ///< "peak" / "sustained"

struct HotspotFlight {
  std::uint32_t id = 0;  ///< index in TrailSet::flights()
  std::string callsign, icao24;
};

struct Hotspot {
  std::uint32_t volume = 0;  ///< index into CountsResult::volumes
  HotspotKind kind = HotspotKind::peak;
  std::uint32_t first_step = 0, last_step = 0;  ///< periods of the run, inclusive
  double start = 0, end = 0;                    ///< Unix seconds: first period's start, last period's end
  std::uint32_t peak = 0;                       ///< largest occupancy in the run
  double peak_time = 0;                         ///< start of the first period reaching it
  double threshold = 0, excess = 0;             ///< excess = peak - threshold (> 0)
  std::vector<HotspotFlight> flights;           ///< counted in some period of the run, by id
};

/// One volume-hour of the complexity score (only those with flight time > 0 are listed).
struct ComplexityCell {
  std::uint32_t volume = 0;  ///< index into CountsResult::volumes
  std::uint32_t hour = 0;    ///< h: [t0 + 3600h, ...)
  double flight_hours = 0, interaction_hours = 0;
  double horizontal_hours = 0, vertical_hours = 0, speed_hours = 0;
  double adjusted_density() const;  ///< 60 · interaction / flight hours
  double structural_index() const;  ///< (H + V + S) / interaction hours, 0 without interactions
  double score() const;             ///< adjusted_density · structural_index
};

struct CountsResult {
  double t0 = 0, t1 = 0, step_s = 0, duration_s = 0, entry_window_s = 0, entry_step_s = 0;
  Method method = Method::interpolated;
  bool grid = true;                                       ///< volumes are grid cells (else sectors)
  std::uint32_t steps = 0, entry_windows = 0, hours = 0;  ///< K, J, H
  std::uint32_t flights = 0;  ///< flights selected by the query's flight filters that overlap [t0, t1)
  /// Sectors: every sector, in request order. Grid: the cells of the extent with at least one flight
  /// inside at some instant of [t0, t1) (method=samples: one sample inside in [t0, t1), or a complexity
  /// row), ordered by (row, col, layer).
  std::vector<VolumeResult> volumes;
  /// By excess (descending), then start, volume, kind; at most limits::kMaxHotspots (the largest).
  std::vector<Hotspot> hotspots;
  std::uint64_t hotspots_total = 0;  ///< all found, before the cap
  ComplexityParams complexity_params;
  bool has_complexity = false;
  std::vector<ComplexityCell> complexity;  ///< by (volume, hour)
  ComplexityCell complexity_total;         ///< sums over every listed volume-hour (volume and hour 0)

  double step_start(std::uint32_t k) const { return t0 + k * step_s; }
  double window_start(std::uint32_t j) const { return t0 + j * entry_step_s; }

  /// {"t0","t1","step","duration","method","entry_window","entry_step","volumes_kind":"grid"|"sectors",
  ///  "steps","entry_windows","hours","flights",
  ///  "volumes":[{"id","kind":"cell"|"sector","south","north","west","east","lower_m","upper_m",
  ///              "peak","sustained" (null when none),"max_occupancy","total_entries",
  ///              "occupancy":{"step":[k...],"count":[...]},"entries":{"window":[j...],"count":[...]}}],
  ///  "hotspots":[{"volume" (id),"kind","first_step","last_step","start","end","peak","peak_time",
  ///               "threshold","excess","flights":[{"id","callsign","icao24"}]}],"hotspots_total",
  ///  "complexity": null | {"heading_deg","speed_kt","vrate_fpm",
  ///      "cells":[{"volume" (id),"hour","start","flight_hours","interaction_hours","horizontal_hours",
  ///                "vertical_hours","speed_hours","adjusted_density","structural_index","score"}],
  ///      "total":{the same without volume, hour, start}}}
  /// Series are sparse (periods with a zero count are omitted); times are Unix seconds.
  nlohmann::json to_json() const;
  /// CSV, long format, header "volume,series,index,start,end,value": one row per non-zero occupancy
  /// (series "occupancy", index k, the period's start and end) and entry count (series "entries",
  /// index j, the window's start and end), volumes in order, occupancy rows before entry rows.
  void write_csv(std::ostream& out) const;
  /// CSV "volume,kind,first_step,last_step,start,end,peak,peak_time,threshold,excess,flights" with the
  /// flight ids joined by spaces.
  void write_hotspots_csv(std::ostream& out) const;
  /// CSV "volume,hour,start,flight_hours,interaction_hours,horizontal_hours,vertical_hours,speed_hours,
  /// adjusted_density,structural_index,score".
  void write_complexity_csv(std::ostream& out) const;
};

/// Counts as this header describes. validate()s the request first (same errors). Throws
/// Error(payload_too_large, "bbox" on the grid / "sectors") when the answer would hold more than
/// limits::kMaxCongestionResultValues non-zero series values and complexity rows, or the work more than
/// limits::kMaxCongestionPieces inside pieces (nothing is returned then), and Error(cancelled) when
/// `cancel` is set. `progress` is called with stages "inside" (flights done), "counts", "complexity".
CountsResult count(const TrailSet& set, const CountsRequest& request, const ProgressFn& progress = {},
                   const CancelToken* cancel = nullptr);

}  // namespace trailscope::congestion
