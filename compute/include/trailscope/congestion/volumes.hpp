#pragma once
// Airspace volumes for congestion counts: uploaded sectors (a polygon between two flight levels) and the
// default regular grid of 20 NM x 20 NM x 3,000 ft cells on which the Eurocontrol Performance Review Unit
// defines its traffic complexity score (EUROCONTROL PRU, "Complexity Metrics for ANSP Benchmarking
// Analysis", 2006). counts.hpp counts flights in them.
//
// Coordinates are degrees (longitude, latitude, WGS 84 as the trails carry them) and the volumes are
// prisms in (longitude, latitude, altitude) space: a flight's position between two samples moves on a
// straight line in that space (positions.hpp interpolates lat, lon and alt linearly in time), so the
// time a flight spends inside a volume is found exactly by clipping each segment against the prism.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trailscope/trails/query.hpp"

namespace trailscope::congestion {

/// Metres in one foot (international foot) and in one nautical mile.
inline constexpr double kMetresPerFoot = 0.3048;
inline constexpr double kMetresPerNauticalMile = 1852.0;

/// Metres of a flight level: FL x 100 ft (pressure altitude against the standard atmosphere, which is
/// what the trails' barometric altitude is).
inline constexpr double flight_level_to_metres(double fl) {
  return fl * 100.0 * kMetresPerFoot;
}

// --- sectors ---------------------------------------------------------------------------------------

/// An uploaded airspace volume: the prism of a simple polygon between two altitudes.
///
/// Inside means: the point (lon, lat) lies in the polygon or on its boundary (a closed set, so a flight
/// that only touches an edge or grazes a corner is inside for that instant), and lower_m <= alt <=
/// upper_m (both edges included). A position with an unknown altitude is inside no sector.
/// Longitudes are compared as they are: a ring never crosses 180° (parse_sectors refuses one that
/// does), and a flight crossing 180° is split there (see counts.hpp).
struct Sector {
  std::string name;  ///< unique within one request; 1..limits::kMaxSectorNameLength characters
  /// The outer ring, [lon, lat] degrees, lon in [-180, 180], lat in [-90, 90], WITHOUT the closing
  /// vertex that GeoJSON repeats: at least 3 distinct vertices, no two consecutive equal, no edge
  /// crossing another (a simple polygon), either orientation.
  std::vector<std::array<double, 2>> ring;
  double lower_fl = 0, upper_fl = 0;  ///< flight levels as given, 0 <= lower_fl < upper_fl <= 999
  double lower_m = 0, upper_m = 0;    ///< the same in metres (flight_level_to_metres)
  /// Flights; the occupancy must EXCEED a threshold to make a hotspot (counts.hpp). Absent: the
  /// request's threshold applies, if it has one. Finite and >= 0 when present.
  std::optional<double> peak, sustained;
};

/// Parses a GeoJSON FeatureCollection of Polygon features, one sector per feature, in order:
///   {"type": "FeatureCollection", "features": [
///     {"type": "Feature", "geometry": {"type": "Polygon", "coordinates": [[[lon, lat], ...]]},
///      "properties": {"name": "EDUUUTAS", "lower_fl": 245, "upper_fl": 660,
///                     "peak": 40, "sustained": 32}}]}       (peak and sustained optional)
/// The ring may or may not repeat its first vertex at the end; a third coordinate (altitude) of a
/// position is ignored. Unknown properties are ignored.
/// Throws Error(unprocessable, "sectors") with a message naming the feature ("feature 3 (\"EDUUUTAS\"):
/// ...", or "feature 3: ..." before the name is known) when:
///   - the document is not a FeatureCollection, `features` is not an array or is empty;
///   - a feature is not a Feature, has no Polygon geometry (MultiPolygon and other types are refused:
///     upload one feature per part), or its polygon has holes (more than one ring: refused, since a
///     sector with a hole is two sectors to a flow manager);
///   - a position is not an array of 2 or 3 finite numbers, lon is outside [-180, 180] or lat outside
///     [-90, 90];
///   - the ring has fewer than 3 distinct vertices, zero area, two consecutive equal vertices, an edge
///     with |Δlon| > 180° (a ring crossing 180°: split it into two sectors at the antimeridian), or two
///     edges that cross or touch other than consecutive edges at their shared vertex (self-intersection);
///   - name is missing, not a string, empty, longer than limits::kMaxSectorNameLength, or repeats an
///     earlier feature's name;
///   - lower_fl / upper_fl are missing, not numbers, outside [0, 999], or lower_fl >= upper_fl;
///   - peak / sustained are present but not finite numbers >= 0 (null counts as absent).
/// Throws Error(payload_too_large, "sectors") above limits::kMaxSectors features or
/// limits::kMaxSectorVertices vertices in one ring (checked before any ring is examined).
std::vector<Sector> parse_sectors(const nlohmann::json& geojson);

/// The sectors back as the FeatureCollection parse_sectors reads (rings closed, properties name,
/// lower_fl, upper_fl, and peak / sustained when present): parse_sectors(sectors_to_geojson(s)) == s.
nlohmann::json sectors_to_geojson(const std::vector<Sector>& sectors);

/// Whether (lon, lat) lies in the sector's polygon or on its boundary (altitude not considered).
bool polygon_contains(const Sector& s, double lon, double lat);

// --- the grid --------------------------------------------------------------------------------------
//
// The default volumes: cells of 20 NM x 20 NM x 3,000 ft, as the PRU complexity score uses. Exactly:
//   - rows: bands of 20' (1/3°) of latitude, since 1' of latitude is 1 NM; row r covers
//     [-90 + r/3, -90 + (r+1)/3), r in [0, 540);
//   - columns: in row r, bands of longitude 20 NM wide at the row's middle latitude
//     φ_r = -90 + (r + 0.5)/3, i.e. width w_r = (1/3°) / cos φ_r; column c covers
//     [-180 + c·w_r, -180 + (c+1)·w_r), c in [0, ceil(360 / w_r)); the last column of a row is cut at
//     180° (narrower); lon = 180 is taken as -180 (column 0);
//   - layers: layer l covers altitudes [l·3000 ft, (l+1)·3000 ft) (metres: l·914.4), l any integer
//     (negative below the standard-atmosphere zero, as airports below sea level give).
// Cells are half-open, so they partition space: every position with a known altitude is in exactly one
// cell (a point on a boundary belongs to the cell on its north / east / upper side; lat = 90 belongs to
// row 539). Rows are not aligned across latitudes (each row has its own column width): a cell is an
// axis-aligned box in (lon, lat, alt), which is what makes the exact segment clipping cheap.
// A cell's id is "r<row>c<col>l<layer>", e.g. "r405c540l11" (row 405 starts at 45°N; layer 11 is
// FL330-FL360); stable across requests and releases.

/// One grid cell by its integer coordinates.
struct GridCell {
  int row = 0, col = 0, layer = 0;
  bool operator==(const GridCell&) const = default;
};

/// The cell's extent; south/west/lower are inside the cell, north/east/upper are not (except lat 90).
struct CellBounds {
  double south = 0, north = 0, west = 0, east = 0;  ///< degrees
  double lower_m = 0, upper_m = 0;                  ///< metres
};

/// Rows of the grid (540) and the layer height (3,000 ft in metres).
inline constexpr int kGridRows = 540;
inline constexpr double kGridLayerMetres = 3000.0 * kMetresPerFoot;

/// Width in degrees of longitude of the columns of row `row` (w_r above); row in [0, kGridRows).
double grid_column_width(int row);
/// Number of columns of row `row`: ceil(360 / w_r).
int grid_columns(int row);
/// The cell holding (lat, lon, alt_m): lat in [-90, 90], lon in [-180, 180] (180 taken as -180), alt
/// finite. Throws invalid_argument("lat"/"lon"/"alt") for values out of range or not finite.
GridCell grid_cell_at(double lat, double lon, double alt_m);

/// The boundaries of the rows, computed once per process: what a cell lookup reads.
struct GridRowTable {
  double south[kGridRows];      ///< southern boundary of row r, -90 + r/3 (degrees)
  double width[kGridRows];      ///< column width w_r (degrees of longitude)
  double inv_width[kGridRows];  ///< 1 / w_r: a first guess of the column only
  int columns[kGridRows];       ///< ceil(360 / w_r)
  static const GridRowTable& get();
};

// The parts of grid_cell_at, inline and without its argument checks, for loops that look up a cell per
// sample (congestion counts): the same answers for every argument grid_cell_at accepts (grid_cell_at
// is grid_cell_at_unchecked plus the checks). The caller guarantees lat in [-90, 90], lon in
// [-180, 180] and a finite alt_m with |alt_m| <= 1e7 (anything else, NaN included, is undefined
// behaviour: the casts below need finite values in range). Each takes a first guess by one
// multiplication, then steps to the one row, column or layer whose boundaries (the exact doubles
// south[r], -180 + c·w_r, l·kGridLayerMetres) hold the value: the answer depends on those boundaries
// only, never on how the guess rounds.

/// Row of lat (lat = 90 is in the last row).
inline int grid_row_at(const GridRowTable& t, double lat) noexcept {
  if (lat >= 90) return kGridRows - 1;
  int r = static_cast<int>((lat + 90.0) * 3.0);  // >= 0: truncation is floor
  r = r > kGridRows - 1 ? kGridRows - 1 : r;
  while (r > 0 && lat < t.south[r]) --r;
  while (r + 1 < kGridRows && lat >= t.south[r + 1]) ++r;
  return r;
}
/// Column of lon in row `row` (lon = 180 is taken as -180).
inline int grid_col_at(const GridRowTable& t, int row, double lon) noexcept {
  if (lon >= 180) lon = -180;
  const double w = t.width[row];
  const int n = t.columns[row];
  int c = static_cast<int>((lon + 180.0) * t.inv_width[row]);  // >= 0: truncation is floor
  c = c > n - 1 ? n - 1 : c;
  while (c > 0 && lon < -180.0 + c * w) --c;
  while (c + 1 < n && lon >= -180.0 + (c + 1) * w) ++c;
  return c;
}
/// Layer of alt_m (metres; negative below the zero altitude).
inline int grid_layer_at(double alt_m) noexcept {
  int l = static_cast<int>(alt_m * (1.0 / kGridLayerMetres));  // truncation: off by at most one
  while (alt_m < l * kGridLayerMetres) --l;
  while (alt_m >= (l + 1) * kGridLayerMetres) ++l;
  return l;
}
inline GridCell grid_cell_at_unchecked(const GridRowTable& t, double lat, double lon, double alt_m) noexcept {
  const int r = grid_row_at(t, lat);
  return {r, grid_col_at(t, r, lon), grid_layer_at(alt_m)};
}
CellBounds grid_cell_bounds(const GridCell& c);
/// "r<row>c<col>l<layer>".
std::string grid_cell_id(const GridCell& c);
/// Reads an id grid_cell_id writes; throws invalid_argument("cell") for anything else, or a row/column
/// outside the grid.
GridCell parse_grid_cell_id(const std::string& id);

/// The grid extent of a request: the cells meeting `bbox` (west > east crosses 180°) and the altitude
/// band [alt_min_m, alt_max_m] (closed). Cells are whole: a cell partly outside the bbox is in the
/// extent and counts flights anywhere in it.
struct GridExtent {
  BBox bbox;
  double alt_min_m = 0, alt_max_m = 0;
  int row_min = 0, row_max = 0;      ///< rows meeting the bbox, inclusive
  int layer_min = 0, layer_max = 0;  ///< layers meeting the band, inclusive
  bool contains(const GridCell& c) const;
  /// Number of cells in the extent (sum over its rows of the columns meeting the bbox, times layers).
  std::uint64_t cell_count() const;
};

/// Builds the extent. Throws invalid_argument("bbox") for south > north or coordinates out of range,
/// invalid_argument("alt_min"/"alt_max") for non-finite values or alt_min_m > alt_max_m, and
/// Error(payload_too_large, "bbox") when cell_count() exceeds limits::kMaxGridCells.
GridExtent make_grid_extent(const BBox& bbox, double alt_min_m, double alt_max_m);

}  // namespace trailscope::congestion
