// node-link JSON with a number beyond double's range ("1e999"): nlohmann::json reports it as out_of_range,
// not as a parse_error, and parse_graph once let that escape as a foreign exception (an HTTP 500 on
// upload). Same fault as the depth-video manifest's, which the depth_pack fuzz harness found.
#include <gtest/gtest.h>

#include "test_support.hpp"
#include "trailscope/bundling/graph_io.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::bundling {
namespace {

TEST(NodeLinkJson, NumberOverflowIsARefusal) {
  const GraphFormat node_link = GraphFormat::node_link;
  for (const GraphFormat* format : {static_cast<const GraphFormat*>(nullptr), &node_link}) {
    try {
      parse_graph(
          R"({"nodes":[{"id":0,"x":1e999,"y":0},{"id":1,"x":1,"y":1}],"links":[{"source":0,"target":1}]})",
          {}, format);
      ADD_FAILURE() << "parsed x = 1e999";
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), Error::Kind::unprocessable);
      EXPECT_EQ(e.param(), "input");
      EXPECT_EQ(std::string(e.what()),
                "node_link: JSON error: [json.exception.out_of_range.406] number overflow parsing '1e999'");
    }
  }
}

}  // namespace
}  // namespace trailscope::bundling
