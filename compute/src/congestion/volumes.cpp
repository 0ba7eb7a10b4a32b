#include "trailscope/congestion/volumes.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>
#include <set>

#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/core/text.hpp"

namespace trailscope::congestion {

namespace {

using Pt = std::array<double, 2>;  // lon, lat

Error unprocessable(const std::string& detail) {
  return Error(Error::Kind::unprocessable, "sectors", detail);
}

// Orientation of c against the line a->b: > 0 left, < 0 right, 0 on it.
double orient(const Pt& a, const Pt& b, const Pt& c) {
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}
int sign(double v) {
  return (v > 0) - (v < 0);
}

// c lies on the closed segment a-b, given that the three are collinear.
bool within(const Pt& a, const Pt& b, const Pt& c) {
  return std::min(a[0], b[0]) <= c[0] && c[0] <= std::max(a[0], b[0]) && std::min(a[1], b[1]) <= c[1] &&
         c[1] <= std::max(a[1], b[1]);
}

// The closed segments p1-p2 and q1-q2 share a point.
bool segments_meet(const Pt& p1, const Pt& p2, const Pt& q1, const Pt& q2) {
  const int d1 = sign(orient(q1, q2, p1)), d2 = sign(orient(q1, q2, p2));
  const int d3 = sign(orient(p1, p2, q1)), d4 = sign(orient(p1, p2, q2));
  if (d1 * d2 < 0 && d3 * d4 < 0) return true;
  if (d1 == 0 && within(q1, q2, p1)) return true;
  if (d2 == 0 && within(q1, q2, p2)) return true;
  if (d3 == 0 && within(p1, p2, q1)) return true;
  if (d4 == 0 && within(p1, p2, q2)) return true;
  return false;
}

std::string label(std::size_t i, const std::string& name) {
  std::string s = "feature " + std::to_string(i);
  if (!name.empty()) s += " (\"" + name + "\")";
  return s + ": ";
}

double number_property(const nlohmann::json& props, const char* key, const std::string& where, bool required,
                       bool& present) {
  present = false;
  const auto it = props.find(key);
  if (it == props.end() || it->is_null()) {
    if (required) throw unprocessable(where + "property '" + key + "' is missing");
    return 0;
  }
  if (!it->is_number()) throw unprocessable(where + "property '" + key + "' must be a number");
  const double v = it->get<double>();
  if (!std::isfinite(v)) throw unprocessable(where + "property '" + key + "' must be finite");
  present = true;
  return v;
}

double row_south(int r) {
  return -90.0 + r / 3.0;
}

}  // namespace

bool polygon_contains(const Sector& s, double lon, double lat) {
  const Pt p{lon, lat};
  const auto& ring = s.ring;
  const std::size_t n = ring.size();
  bool inside = false;
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Pt& a = ring[j];
    const Pt& b = ring[i];
    if (orient(a, b, p) == 0 && within(a, b, p)) return true;  // on the boundary: the set is closed
    // Crossing number (W. R. Franklin's PNPOLY): the edge straddles the horizontal line through p and
    // crosses it to the right of p.
    if ((a[1] > lat) != (b[1] > lat)) {
      const double x = a[0] + (lat - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
      if (lon < x) inside = !inside;
    }
  }
  return inside;
}

std::vector<Sector> parse_sectors(const nlohmann::json& doc) {
  if (!doc.is_object() || doc.value("type", nlohmann::json()) != "FeatureCollection")
    throw unprocessable("sectors must be a GeoJSON FeatureCollection");
  const auto it = doc.find("features");
  if (it == doc.end() || !it->is_array())
    throw unprocessable("sectors: the FeatureCollection has no 'features' array");
  const auto& features = *it;
  if (features.empty()) throw unprocessable("sectors: the FeatureCollection has no features");
  if (features.size() > limits::kMaxSectors)
    throw Error(Error::Kind::payload_too_large, "sectors",
                "sectors: " + std::to_string(features.size()) + " features, more than the limit of " +
                    std::to_string(limits::kMaxSectors));
  // Sizes first, so that no ring is examined in a request that will be refused anyway.
  for (std::size_t i = 0; i < features.size(); ++i) {
    const auto& f = features[i];
    if (!f.is_object()) continue;
    const auto g = f.find("geometry");
    if (g == f.end() || !g->is_object()) continue;
    const auto c = g->find("coordinates");
    if (c == g->end() || !c->is_array() || c->empty() || !(*c)[0].is_array()) continue;
    if ((*c)[0].size() > limits::kMaxSectorVertices + 1)
      throw Error(Error::Kind::payload_too_large, "sectors",
                  "feature " + std::to_string(i) + ": " + std::to_string((*c)[0].size()) +
                      " positions in the ring, more than the limit of " +
                      std::to_string(limits::kMaxSectorVertices) + " vertices");
  }

  std::vector<Sector> out;
  out.reserve(features.size());
  std::set<std::string> names;
  for (std::size_t i = 0; i < features.size(); ++i) {
    const auto& f = features[i];
    std::string where = label(i, "");
    if (!f.is_object() || f.value("type", nlohmann::json()) != "Feature")
      throw unprocessable(where + "not a GeoJSON Feature");
    Sector s;
    const auto props_it = f.find("properties");
    if (props_it == f.end() || !props_it->is_object()) throw unprocessable(where + "no 'properties' object");
    const auto& props = *props_it;
    const auto name_it = props.find("name");
    if (name_it == props.end() || name_it->is_null())
      throw unprocessable(where + "property 'name' is missing");
    if (!name_it->is_string()) throw unprocessable(where + "property 'name' must be a string");
    s.name = name_it->get<std::string>();
    if (s.name.empty()) throw unprocessable(where + "property 'name' is empty");
    if (s.name.size() > limits::kMaxSectorNameLength)
      throw unprocessable(where + "property 'name' is longer than " +
                          std::to_string(limits::kMaxSectorNameLength) + " bytes");
    if (!names.insert(s.name).second) throw unprocessable(label(i, s.name) + "the name is already used");
    where = label(i, s.name);

    bool present = false;
    s.lower_fl = number_property(props, "lower_fl", where, true, present);
    s.upper_fl = number_property(props, "upper_fl", where, true, present);
    if (s.lower_fl < 0 || s.lower_fl > 999) throw unprocessable(where + "lower_fl must lie in [0, 999]");
    if (s.upper_fl < 0 || s.upper_fl > 999) throw unprocessable(where + "upper_fl must lie in [0, 999]");
    if (s.lower_fl >= s.upper_fl) throw unprocessable(where + "lower_fl must be below upper_fl");
    s.lower_m = flight_level_to_metres(s.lower_fl);
    s.upper_m = flight_level_to_metres(s.upper_fl);
    for (const char* key : {"peak", "sustained"}) {
      const double v = number_property(props, key, where, false, present);
      if (!present) continue;
      if (v < 0) throw unprocessable(where + "property '" + key + "' must be >= 0");
      (std::string(key) == "peak" ? s.peak : s.sustained) = v;
    }

    const auto g = f.find("geometry");
    if (g == f.end() || !g->is_object()) throw unprocessable(where + "no geometry");
    const auto type = g->value("type", nlohmann::json());
    if (type != "Polygon")
      throw unprocessable(where + "the geometry must be a Polygon" +
                          (type.is_string() ? ", not a " + type.get<std::string>() : std::string()) +
                          " (upload one feature per part)");
    const auto c = g->find("coordinates");
    if (c == g->end() || !c->is_array() || c->empty() || !(*c)[0].is_array())
      throw unprocessable(where + "the Polygon has no coordinates");
    if (c->size() > 1)
      throw unprocessable(where + "the Polygon has holes; a sector is one ring (split it into sectors)");
    for (std::size_t k = 0; k < (*c)[0].size(); ++k) {
      const auto& p = (*c)[0][k];
      if (!p.is_array() || p.size() < 2 || p.size() > 3 || !p[0].is_number() || !p[1].is_number())
        throw unprocessable(where + "position " + std::to_string(k) + " is not [lon, lat]");
      const double lon = p[0].get<double>(), lat = p[1].get<double>();
      if (!std::isfinite(lon) || !std::isfinite(lat) || lon < -180 || lon > 180 || lat < -90 || lat > 90)
        throw unprocessable(where + "position " + std::to_string(k) +
                            " is outside lon [-180, 180], lat [-90, 90]");
      s.ring.push_back({lon, lat});
    }
    if (s.ring.size() > 1 && s.ring.front() == s.ring.back()) s.ring.pop_back();
    for (std::size_t k = 0; k + 1 < s.ring.size(); ++k)
      if (s.ring[k] == s.ring[k + 1])
        throw unprocessable(where + "positions " + std::to_string(k) + " and " + std::to_string(k + 1) +
                            " are equal");
    std::set<Pt> distinct(s.ring.begin(), s.ring.end());
    if (distinct.size() < 3) throw unprocessable(where + "the ring needs at least 3 distinct vertices");
    const std::size_t n = s.ring.size();
    double area2 = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const Pt& a = s.ring[k];
      const Pt& b = s.ring[(k + 1) % n];
      if (std::fabs(b[0] - a[0]) > 180)
        throw unprocessable(where + "edge " + std::to_string(k) +
                            " crosses 180° of longitude; split the sector at the antimeridian");
      area2 += a[0] * b[1] - b[0] * a[1];
    }
    if (area2 == 0) throw unprocessable(where + "the ring has zero area");
    // Simple polygon: edges meet only consecutive edges, at their shared vertex. O(n²), bounded by
    // limits::kMaxSectorVertices.
    for (std::size_t a = 0; a < n; ++a) {
      const Pt& p1 = s.ring[a];
      const Pt& p2 = s.ring[(a + 1) % n];
      for (std::size_t b = a + 1; b < n; ++b) {
        const Pt& q1 = s.ring[b];
        const Pt& q2 = s.ring[(b + 1) % n];
        const bool next = b == a + 1, wrap = a == 0 && b == n - 1;
        if (next || wrap) {
          // Consecutive: they share one vertex; they must not fold back onto each other.
          const Pt& shared = next ? p2 : p1;
          const Pt& other_a = next ? p1 : p2;
          const Pt& other_b = next ? q2 : q1;
          if (orient(other_a, shared, other_b) == 0 && within(other_a, other_b, shared) == false)
            throw unprocessable(where + "edges " + std::to_string(a) + " and " + std::to_string(b) +
                                " overlap (the ring folds back on itself)");
          continue;
        }
        if (segments_meet(p1, p2, q1, q2))
          throw unprocessable(where + "edges " + std::to_string(a) + " and " + std::to_string(b) +
                              " intersect (the ring must be a simple polygon)");
      }
    }
    out.push_back(std::move(s));
  }
  return out;
}

nlohmann::json sectors_to_geojson(const std::vector<Sector>& sectors) {
  nlohmann::json features = nlohmann::json::array();
  for (const auto& s : sectors) {
    nlohmann::json ring = nlohmann::json::array();
    for (const auto& p : s.ring) ring.push_back({p[0], p[1]});
    if (!s.ring.empty()) ring.push_back({s.ring.front()[0], s.ring.front()[1]});
    nlohmann::json props = {{"name", s.name}, {"lower_fl", s.lower_fl}, {"upper_fl", s.upper_fl}};
    if (s.peak) props["peak"] = *s.peak;
    if (s.sustained) props["sustained"] = *s.sustained;
    features.push_back({{"type", "Feature"},
                        {"geometry", {{"type", "Polygon"}, {"coordinates", nlohmann::json::array({ring})}}},
                        {"properties", props}});
  }
  return {{"type", "FeatureCollection"}, {"features", features}};
}

// --- grid ------------------------------------------------------------------------------------------

const GridRowTable& GridRowTable::get() {
  static const GridRowTable t = [] {
    GridRowTable t;
    for (int r = 0; r < kGridRows; ++r) {
      const double mid = (-90.0 + (r + 0.5) / 3.0) * std::numbers::pi / 180.0;
      t.south[r] = row_south(r);
      t.width[r] = (1.0 / 3.0) / std::cos(mid);
      t.inv_width[r] = 1.0 / t.width[r];
      t.columns[r] = static_cast<int>(std::ceil(360.0 / t.width[r]));
    }
    return t;
  }();
  return t;
}

double grid_column_width(int row) {
  return GridRowTable::get().width[row];
}

int grid_columns(int row) {
  return GridRowTable::get().columns[row];
}

namespace {
int row_of(double lat) {
  return grid_row_at(GridRowTable::get(), lat);
}
int col_of(int row, double lon) {
  return grid_col_at(GridRowTable::get(), row, lon);
}
int layer_of(double alt_m) {
  return grid_layer_at(alt_m);
}
}  // namespace

GridCell grid_cell_at(double lat, double lon, double alt_m) {
  if (!(lat >= -90 && lat <= 90)) throw invalid_argument("lat", "lat must lie in [-90, 90]");
  if (!(lon >= -180 && lon <= 180)) throw invalid_argument("lon", "lon must lie in [-180, 180]");
  if (!std::isfinite(alt_m)) throw invalid_argument("alt", "alt must be a finite altitude in metres");
  if (std::fabs(alt_m) > 1e7) throw invalid_argument("alt", "alt is out of range");
  return grid_cell_at_unchecked(GridRowTable::get(), lat, lon, alt_m);
}

CellBounds grid_cell_bounds(const GridCell& c) {
  const double w = grid_column_width(c.row);
  CellBounds b;
  b.south = row_south(c.row);
  b.north = c.row + 1 == kGridRows ? 90.0 : row_south(c.row + 1);
  b.west = -180.0 + c.col * w;
  b.east = std::min(180.0, -180.0 + (c.col + 1) * w);
  b.lower_m = c.layer * kGridLayerMetres;
  b.upper_m = (c.layer + 1) * kGridLayerMetres;
  return b;
}

std::string grid_cell_id(const GridCell& c) {
  // Formatted in one buffer: a grid answer names tens of thousands of cells.
  char buf[40];
  std::size_t n = 0;
  for (const auto& [tag, v] : {std::pair{'r', c.row}, std::pair{'c', c.col}, std::pair{'l', c.layer}}) {
    buf[n++] = tag;
    n = static_cast<std::size_t>(std::to_chars(buf + n, buf + sizeof buf, v).ptr - buf);
  }
  return std::string(buf, n);
}

GridCell parse_grid_cell_id(const std::string& id) {
  const auto bad = [&] {
    return invalid_argument("cell", "cell: '" + id + "' is not a grid cell id like r405c540l11");
  };
  GridCell c;
  std::size_t pos = 0;
  const auto read_int = [&](char tag, bool allow_negative) {
    if (pos >= id.size() || id[pos] != tag) throw bad();
    ++pos;
    const std::size_t start = pos;
    if (allow_negative && pos < id.size() && id[pos] == '-') ++pos;
    const std::size_t digits = pos;
    while (pos < id.size() && std::isdigit(static_cast<unsigned char>(id[pos]))) ++pos;
    if (pos == digits || pos - digits > 6) throw bad();
    if (id[digits] == '0' && pos - digits > 1) throw bad();  // one spelling per cell
    return std::stoi(id.substr(start, pos - start));
  };
  c.row = read_int('r', false);
  c.col = read_int('c', false);
  c.layer = read_int('l', true);
  if (pos != id.size()) throw bad();
  if (c.row >= kGridRows || c.col >= grid_columns(c.row) || (c.layer == 0 && id.ends_with("-0"))) throw bad();
  return c;
}

namespace {
// Columns of `row` meeting [west, east] (west <= east), inclusive.
std::pair<int, int> column_range(int row, double west, double east) {
  const int lo = col_of(row, west);
  const int hi = east >= 180 ? grid_columns(row) - 1 : col_of(row, east);
  return {lo, hi};
}
}  // namespace

bool GridExtent::contains(const GridCell& c) const {
  if (c.row < row_min || c.row > row_max || c.layer < layer_min || c.layer > layer_max) return false;
  const auto in = [&](double w, double e) {
    const auto [lo, hi] = column_range(c.row, w, e);
    return c.col >= lo && c.col <= hi;
  };
  if (bbox.west <= bbox.east) return in(bbox.west, bbox.east);
  return in(bbox.west, 180) || in(-180, bbox.east);
}

std::uint64_t GridExtent::cell_count() const {
  std::uint64_t cols = 0;
  for (int r = row_min; r <= row_max; ++r) {
    if (bbox.west <= bbox.east) {
      const auto [lo, hi] = column_range(r, bbox.west, bbox.east);
      cols += static_cast<std::uint64_t>(hi - lo + 1);
    } else {
      const auto [lo1, hi1] = column_range(r, bbox.west, 180);
      const auto [lo2, hi2] = column_range(r, -180, bbox.east);
      // The two ranges can share column 0 / the last column only when they overlap; count the union.
      std::uint64_t n = static_cast<std::uint64_t>(hi1 - lo1 + 1) + static_cast<std::uint64_t>(hi2 - lo2 + 1);
      if (lo1 <= hi2) n = static_cast<std::uint64_t>(grid_columns(r));
      cols += n;
    }
  }
  return cols * static_cast<std::uint64_t>(layer_max - layer_min + 1);
}

GridExtent make_grid_extent(const BBox& bbox, double alt_min_m, double alt_max_m) {
  const auto in = [](double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; };
  if (!in(bbox.west, -180, 180) || !in(bbox.east, -180, 180) || !in(bbox.south, -90, 90) ||
      !in(bbox.north, -90, 90) || bbox.south > bbox.north)
    throw invalid_argument("bbox", "bbox: need west, east in [-180, 180] and -90 <= south <= north <= 90");
  if (!std::isfinite(alt_min_m) || std::fabs(alt_min_m) > 1e6)
    throw invalid_argument("alt_min", "alt_min must be a finite altitude");
  if (!std::isfinite(alt_max_m) || std::fabs(alt_max_m) > 1e6)
    throw invalid_argument("alt_max", "alt_max must be a finite altitude");
  if (alt_min_m > alt_max_m) throw invalid_argument("alt_max", "alt_max must not be below alt_min");
  GridExtent e;
  e.bbox = bbox;
  e.alt_min_m = alt_min_m;
  e.alt_max_m = alt_max_m;
  e.row_min = row_of(bbox.south);
  e.row_max = row_of(bbox.north);
  e.layer_min = layer_of(alt_min_m);
  e.layer_max = layer_of(alt_max_m);
  const std::uint64_t n = e.cell_count();
  if (n > limits::kMaxGridCells)
    throw Error(Error::Kind::payload_too_large, "bbox",
                "the grid extent has " + std::to_string(n) + " cells, more than the limit of " +
                    std::to_string(limits::kMaxGridCells) + "; narrow bbox or alt_min/alt_max");
  return e;
}

}  // namespace trailscope::congestion
