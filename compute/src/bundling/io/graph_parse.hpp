#pragma once
// Private helpers of the graph readers (graph_io.cpp and graph_*.cpp): building a Graph from node
// positions and edges, the limits, and error messages that name the format and the line.
#include <cstddef>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "trailscope/bundling/graph_io.hpp"

namespace trailscope::bundling::detail {

/// Error(unprocessable, `param`) "FORMAT line N: what" (line 0: no line).
[[noreturn]] void fail(const char* format, std::size_t line, const std::string& what,
                       const std::string& param = "input");
/// The 1-based line of byte `offset` of `text`.
std::size_t line_of(std::string_view text, std::size_t offset);
/// `s` in single quotes, ASCII only, cut after `max` characters (for messages about damaged input).
std::string quote(std::string_view s, std::size_t max = 40);
/// Parses all of `s` (trimmed) as a finite double; false otherwise.
bool parse_double(std::string_view s, double& out);

/// Collects edges between named nodes: unknown ids and self-loops (both ends at one position) are
/// counted in `skipped`; `nodes` becomes the number of distinct endpoint positions of the kept edges.
class GraphBuilder {
 public:
  explicit GraphBuilder(GraphFormat format) { graph_.format = format; }
  void add_node(const std::string& id, double x, double y) { pos_[id] = {x, y}; }
  bool has_node(const std::string& id) const { return pos_.count(id) != 0; }
  /// Adds the edge source → target (ids); throws payload_too_large beyond kMaxBundleEdges.
  void add_edge(const std::string& source, const std::string& target, double weight);
  /// Adds a straight edge by coordinates (self-contained CSV).
  void add_edge(double x0, double y0, double x1, double y1, double weight);
  void skip() { ++graph_.skipped; }
  /// The graph; throws unprocessable ("no edge") when none was kept.
  Graph finish(bool geographic, bool y_up);

 private:
  struct Pos {
    double x, y;
  };
  Graph graph_;
  std::unordered_map<std::string, Pos> pos_;
};

/// Throws payload_too_large when `edges` polylines or `points` points exceed the bundling limits.
void check_limits(std::size_t edges, std::size_t points);

Graph parse_graphml(std::string_view bytes);
Graph parse_node_link(std::string_view bytes);
Graph parse_od_csv(std::string_view bytes, std::string_view nodes_csv);
Graph parse_trl(std::string_view bytes);

}  // namespace trailscope::bundling::detail
