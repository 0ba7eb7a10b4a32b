// Origin–destination CSV (RFC 4180: a header row, commas, optional double quotes). Two forms:
//  - self-contained: one edge per row with its coordinates, columns (case-insensitive)
//      x1,y1,x2,y2 | source_x,source_y,target_x,target_y                          (plane coordinates)
//      origin_lon,origin_lat,dest_lon,dest_lat | lon1,lat1,lon2,lat2 |
//      origin_longitude,origin_latitude,destination_longitude,destination_latitude |
//      src_lon,src_lat,dst_lon,dst_lat                                            (degrees)
//  - by name: origin|source|from|src, destination|dest|target|to|dst, and an optional count|weight|value,
//    with a nodes table keyed by iata|id|name holding latitude|lat and longitude|lon (degrees) or x, y.
// Degrees are projected to EPSG:3857 metres, y north (so y_up), and must lie in [-90, 90] × [-180, 180].
#include <array>
#include <optional>
#include <cctype>
#include <string>
#include <vector>

#include "bundling/io/graph_parse.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/geo/web_mercator.hpp"

namespace trailscope::bundling::detail {
namespace {

constexpr const char* kFormat = "od_csv";

struct Row {
  std::size_t line;
  std::vector<std::string> fields;
};
struct Table {
  std::vector<std::string> header;  ///< lower case, trimmed
  std::vector<Row> rows;
  std::optional<std::size_t> column(std::initializer_list<const char*> names) const {
    for (const char* n : names)
      for (std::size_t i = 0; i < header.size(); ++i)
        if (header[i] == n) return i;
    return std::nullopt;
  }
};

std::string trim_lower(std::string s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
  std::size_t b = 0;
  while (b < s.size() && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
  s.erase(0, b);
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

/// Splits `text` into records (quoted fields may hold commas, quotes as "" and line breaks); blank lines
/// are skipped; every record must have as many fields as the header.
Table read_table(std::string_view text, const char* what, const std::string& param) {
  Table t;
  std::size_t i = 0, line = 1;
  if (text.substr(0, 3) == "\xEF\xBB\xBF") i = 3;
  while (i < text.size()) {
    const std::size_t start_line = line;
    std::vector<std::string> fields(1);
    bool quoted = false, any = false;
    for (; i < text.size(); ++i) {
      const char c = text[i];
      if (quoted) {
        if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
          fields.back() += '"', ++i;
        } else if (c == '"') {
          quoted = false;
        } else {
          if (c == '\n') ++line;
          fields.back() += c;
        }
        continue;
      }
      if (c == '\n') {
        ++line, ++i;
        break;
      }
      if (c == '\r') continue;
      any = true;
      if (c == ',')
        fields.emplace_back();
      else if (c == '"')
        quoted = true;
      else
        fields.back() += c;
    }
    if (quoted) fail(what, start_line, "unterminated quoted field", param);
    if (!any) continue;  // blank line
    if (t.header.empty()) {
      for (auto& f : fields) t.header.push_back(trim_lower(f));
      continue;
    }
    if (fields.size() != t.header.size())
      fail(what, start_line,
           std::to_string(fields.size()) + " fields, the header has " + std::to_string(t.header.size()),
           param);
    t.rows.push_back(Row{start_line, std::move(fields)});
  }
  if (t.header.empty()) fail(what, 0, "no header row", param);
  return t;
}

double field_number(const Row& r, std::size_t col, const Table& t, const char* what,
                    const std::string& param) {
  double v = 0;
  if (!parse_double(r.fields[col], v))
    fail(what, r.line, t.header[col] + " " + quote(r.fields[col]) + " is not a finite number", param);
  return v;
}

/// lon/lat (degrees, checked) → EPSG:3857 metres.
std::array<double, 2> project(double lon, double lat, std::size_t line, const char* what,
                              const std::string& param) {
  if (lat < -90 || lat > 90)
    fail(what, line, "latitude " + std::to_string(lat) + " is outside [-90, 90]", param);
  if (lon < -180 || lon > 180)
    fail(what, line, "longitude " + std::to_string(lon) + " is outside [-180, 180]", param);
  return {geo::lon_to_meters_x(lon), geo::lat_to_meters_y(lat)};
}

struct CoordColumns {
  std::array<const char*, 4> names;
  bool degrees;
};
constexpr CoordColumns kCoordSets[] = {
    {{"x1", "y1", "x2", "y2"}, false},
    {{"source_x", "source_y", "target_x", "target_y"}, false},
    {{"origin_lon", "origin_lat", "dest_lon", "dest_lat"}, true},
    {{"lon1", "lat1", "lon2", "lat2"}, true},
    {{"origin_longitude", "origin_latitude", "destination_longitude", "destination_latitude"}, true},
    {{"src_lon", "src_lat", "dst_lon", "dst_lat"}, true},
};

}  // namespace

Graph parse_od_csv(std::string_view bytes, std::string_view nodes_csv) {
  const Table edges = read_table(bytes, kFormat, "input");
  const auto weight_col = edges.column({"count", "weight", "value"});
  auto weight = [&](const Row& r) {
    return weight_col ? field_number(r, *weight_col, edges, kFormat, "input") : 1.0;
  };
  GraphBuilder builder(GraphFormat::od_csv);

  for (const CoordColumns& set : kCoordSets) {
    std::array<std::size_t, 4> col{};
    bool all = true;
    for (int k = 0; k < 4; ++k) {
      const auto c = edges.column({set.names[k]});
      all = all && c.has_value();
      if (c) col[k] = *c;
    }
    if (!all) continue;
    for (const Row& r : edges.rows) {
      double v[4];
      for (int k = 0; k < 4; ++k) v[k] = field_number(r, col[k], edges, kFormat, "input");
      if (set.degrees) {
        const auto a = project(v[0], v[1], r.line, kFormat, "input");
        const auto b = project(v[2], v[3], r.line, kFormat, "input");
        builder.add_edge(a[0], a[1], b[0], b[1], weight(r));
      } else {
        builder.add_edge(v[0], v[1], v[2], v[3], weight(r));
      }
    }
    return builder.finish(set.degrees, set.degrees);
  }

  const auto from = edges.column({"origin", "source", "from", "src"});
  const auto to = edges.column({"destination", "dest", "target", "to", "dst"});
  if (!from || !to)
    fail(kFormat, 1,
         "the header has neither coordinate columns (x1,y1,x2,y2 or origin_lon,origin_lat,dest_lon,dest_lat) "
         "nor origin,destination names");
  if (nodes_csv.empty())
    throw Error(
        Error::Kind::unprocessable, "nodes",
        "od_csv: edges given by node name need a nodes table (iata, id or name; latitude, longitude)");
  const Table nodes = read_table(nodes_csv, "nodes csv", "nodes");
  const auto key = nodes.column({"iata", "id", "name"});
  auto lat = nodes.column({"latitude", "lat"}), lon = nodes.column({"longitude", "lon"});
  const bool degrees = lat && lon;
  if (!degrees) lat = nodes.column({"y"}), lon = nodes.column({"x"});
  if (!key || !lat || !lon)
    fail("nodes csv", 1, "the header needs iata|id|name and latitude|lat, longitude|lon (or x, y) columns",
         "nodes");
  for (const Row& r : nodes.rows) {
    const double y = field_number(r, *lat, nodes, "nodes csv", "nodes");
    const double x = field_number(r, *lon, nodes, "nodes csv", "nodes");
    if (degrees) {
      const auto p = project(x, y, r.line, "nodes csv", "nodes");
      builder.add_node(r.fields[*key], p[0], p[1]);
    } else {
      builder.add_node(r.fields[*key], x, y);
    }
  }
  for (const Row& r : edges.rows) builder.add_edge(r.fields[*from], r.fields[*to], weight(r));
  return builder.finish(degrees, degrees);
}

}  // namespace trailscope::bundling::detail
