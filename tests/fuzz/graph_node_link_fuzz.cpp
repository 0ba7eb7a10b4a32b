// libFuzzer harness: the node_link graph reader of bundling (compute/src/bundling/io/graph_node_link.cpp)
// through parse_graph() with the format named, as the graph upload route and `trailscope bundle` call it;
// format detection (detect_graph_format) runs on the same bytes first.
#include "fuzz_support.hpp"
#include "trailscope/bundling/graph_io.hpp"

using namespace trailscope;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string_view bytes = fuzz::bytes_of(data, size);
  std::string_view nodes;

  try {
    (void)bundling::detect_graph_format(bytes);
  } catch (const Error& e) {
    fuzz::refuse(e);
  }
  try {
    const auto format = bundling::GraphFormat::node_link;
    const bundling::Graph g = bundling::parse_graph(bytes, nodes, &format);
    // What the bundler relies on: one weight per edge, offsets consistent with the points.
    if (g.weight.size() != g.edges.size() || g.edges.offsets.back() != g.edges.points() ||
        g.edges.x.size() != g.edges.y.size())
      std::abort();
  } catch (const Error& e) {
    fuzz::refuse(e);
  }
  return 0;
}
