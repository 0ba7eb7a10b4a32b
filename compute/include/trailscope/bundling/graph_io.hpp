#pragma once
// Reading graphs and trail sets to bundle. Formats (detected from content, or named):
//  - graphml:   GraphML with node coordinates in data keys named x and y (attr.name) — the FDEB
//               airlines/migrations files; edges refer to node ids; an edge `value`/`weight` key is read
//               as the edge weight.
//  - node_link: networkx node-link JSON, {"nodes":[{"id","x","y"}], "links":[{"source","target"}]}
//               ("edges" is accepted for "links"; source/target may be ids or node indices).
//  - od_csv:    origin–destination CSV. Either self-contained, one row per edge with coordinate columns
//               (x1,y1,x2,y2 | origin_lon,origin_lat,dest_lon,dest_lat | …), or edges by node name
//               (origin,destination[,count]) with a separate nodes CSV (iata|id|name, latitude|lat|y,
//               longitude|lon|x), as vega-datasets flights-airport.csv + airports.csv. Geographic
//               coordinates (lon/lat) are projected to Web Mercator.
//  - trl:       CUBu trail text: a token ending in ':' starts a polyline, then x y pairs; tokens starting
//               with '(' or '<' are skipped (as the original CUBu code's reader does). `.xy` files are the
//               same. A label with a single number (the "maxv: 1.0" header of a bundled file) is a header
//               field: like any polyline of fewer than 2 points it is counted in `skipped`.
// Every error names the format and the line (or element) at fault.
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "trailscope/bundling/polylines.hpp"

namespace trailscope::bundling {

enum class GraphFormat { graphml, node_link, od_csv, trl };
/// Parses "graphml" | "node_link" | "od_csv" | "trl"; throws invalid_argument(param).
GraphFormat parse_graph_format(std::string_view text, const std::string& param = "format");
const char* to_string(GraphFormat f) noexcept;
/// The format of `bytes` by content; throws Error(unsupported_format, `input`) when none fits.
GraphFormat detect_graph_format(std::string_view bytes);

struct Graph {
  Polylines edges;             ///< source coordinates (Web Mercator metres when `geographic`)
  std::vector<double> weight;  ///< per edge (1 when the input has none)
  std::size_t nodes = 0;       ///< distinct endpoint positions of the kept edges (graphs; node
                               ///< records at one position count once); 0 for trails
  GraphFormat format = GraphFormat::trl;
  bool geographic = false;  ///< coordinates were lon/lat and are now Web Mercator metres (EPSG:3857)
  bool y_up = false;        ///< y grows upward (draw flipped); true for geographic input
  std::size_t skipped = 0;  ///< edges dropped: self-loops, unknown nodes, fewer than 2 points
};

/// Parses a graph from memory. `nodes_csv` is the separate nodes table of an od_csv by name (ignored
/// otherwise). Throws Error(unsupported_format, `input`) for an unknown format, Error(unprocessable,
/// `input`) with the line/element for malformed content or when no edge remains ("FORMAT line N: …",
/// "node_link: links[7] …"; `nodes` for a missing or malformed nodes table), and Error(
/// payload_too_large, `input`) beyond limits::kMaxBundleEdges polylines or kMaxBundleInputPoints points.
Graph parse_graph(std::string_view bytes, std::string_view nodes_csv = {},
                  const GraphFormat* format = nullptr);
/// Reads a file (and optional nodes file) and parses it. Throws not_found(`input`/`nodes`) when a
/// file cannot be read, payload_too_large beyond limits::kMaxGraphUploadBytes, else as parse_graph.
Graph read_graph(const std::filesystem::path& path, const std::filesystem::path& nodes_path = {},
                 const GraphFormat* format = nullptr);

/// CUBu .trl text of polylines ("i:" then x y pairs, one polyline per line), for exporting results.
/// Numbers are written in the shortest form that reads back to the same double (std::to_chars).
std::string write_trl(const Polylines& lines);

}  // namespace trailscope::bundling
