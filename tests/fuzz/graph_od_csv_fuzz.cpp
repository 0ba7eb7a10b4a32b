// libFuzzer harness: the od_csv graph reader of bundling (compute/src/bundling/io/graph_od_csv.cpp) through
// parse_graph() with the format named, as the graph upload route and `trailscope bundle` call it; format
// detection (detect_graph_format) runs on the same bytes first.
// The bytes after the first NUL are the separate nodes table of an od_csv by name.
#include "fuzz_support.hpp"
#include "trailscope/bundling/graph_io.hpp"

using namespace trailscope;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string_view bytes = fuzz::bytes_of(data, size);
  std::string_view nodes;
  if (const auto nul = bytes.find('\0'); nul != std::string_view::npos) {
    nodes = bytes.substr(nul + 1);
    bytes = bytes.substr(0, nul);
  }
  try {
    (void)bundling::detect_graph_format(bytes);
  } catch (const Error& e) {
    fuzz::refuse(e);
  }
  try {
    const auto format = bundling::GraphFormat::od_csv;
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
