// libFuzzer harness: the od_csv graph reader of bundling (compute/src/bundling/io/graph_od_csv.cpp); the
// body is fuzz::graph_one (graph_harness.hpp). The bytes after the first NUL are the separate nodes table
// of an od_csv by name.
#include "graph_harness.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace trailscope;
  std::string_view bytes = fuzz::bytes_of(data, size), nodes;
  if (const auto nul = bytes.find('\0'); nul != std::string_view::npos) {
    nodes = bytes.substr(nul + 1);
    bytes = bytes.substr(0, nul);
  }
  return fuzz::graph_one(bytes, nodes, bundling::GraphFormat::od_csv);
}
