#pragma once
// The body of the four graph-reader harnesses (graph_<format>_fuzz.cpp): the bytes through parse_graph()
// with the format named, as the graph upload route and `trailscope bundle` call it; format detection
// (detect_graph_format) runs on the same bytes first.
#include "fuzz_support.hpp"
#include "trailscope/bundling/graph_io.hpp"

namespace trailscope::fuzz {

/// One input of a graph harness: `bytes` the graph, `nodes` the separate nodes table (od_csv by name).
inline int graph_one(std::string_view bytes, std::string_view nodes, bundling::GraphFormat format) {
  try {
    (void)bundling::detect_graph_format(bytes);
  } catch (const Error& e) {
    refuse(e);
  }
  try {
    const bundling::Graph g = bundling::parse_graph(bytes, nodes, &format);
    // What the bundler relies on: one weight per edge, offsets consistent with the points.
    if (g.weight.size() != g.edges.size() || g.edges.offsets.back() != g.edges.points() ||
        g.edges.x.size() != g.edges.y.size())
      std::abort();
  } catch (const Error& e) {
    refuse(e);
  }
  return 0;
}

}  // namespace trailscope::fuzz
