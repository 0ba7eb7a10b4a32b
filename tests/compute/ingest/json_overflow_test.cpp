// A readsb trace with a number beyond double's range ("1e999"): nlohmann::json reports it as out_of_range,
// not as a parse_error, and the reader once let that escape as a foreign exception (an HTTP 500 on
// upload). The same fault as the depth-video manifest's, which the depth_pack fuzz harness found. The
// overflowing number comes after "icao" and "trace", so that detection (which stops at it) still sees a
// readsb trace.
#include <gtest/gtest.h>

#include "ingest_test_helpers.hpp"
#include "trailscope/ingest/ingest.hpp"

namespace trailscope::ingest {
namespace {

TEST(ReadsbTraceJson, NumberOverflowIsARefusal) {
  test::TempDir dir;
  const auto path = dir.path() / "trace.json";
  test::write_text(path, R"({"icao":"abc123","trace":[[0,1,2,1000,100,90,0,0,null]],"timestamp":1e999})");
  for (const bool forced : {false, true}) {
    IngestOptions opts;
    if (forced) opts.format = Format::readsb_trace;
    const auto e = test::catch_error([&] { ingest_file(path.string(), opts); });
    ASSERT_TRUE(e.has_value()) << "forced " << forced;
    EXPECT_EQ(e->kind(), Error::Kind::unprocessable);
    EXPECT_EQ(e->param(), "file");
    EXPECT_EQ(
        std::string(e->what()),
        "invalid JSON in readsb trace: [json.exception.out_of_range.406] number overflow parsing '1e999'");
  }
}

}  // namespace
}  // namespace trailscope::ingest
