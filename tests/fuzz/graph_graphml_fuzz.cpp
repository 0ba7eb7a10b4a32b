// libFuzzer harness: the graphml graph reader of bundling (compute/src/bundling/io/graph_graphml.cpp); the
// body is fuzz::graph_one (graph_harness.hpp).
#include "graph_harness.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace trailscope;
  return fuzz::graph_one(fuzz::bytes_of(data, size), {}, bundling::GraphFormat::graphml);
}
