// A manifest with a number beyond double's range ("1E400"): nlohmann::json reports it as out_of_range, not
// as a parse_error, and the reader once let that escape as a foreign exception (an HTTP 500 on upload).
// Found by the depth_pack fuzz harness (tests/fuzz/regressions/depth_pack/ keeps its input).
#include <gtest/gtest.h>

#include "test_support.hpp"
#include "tof_test_util.hpp"
#include "trailscope/tof/depth_video_io.hpp"
#include "trailscope/tof/synth.hpp"

namespace trailscope::tof {
namespace {
namespace fs = std::filesystem;

TEST(DepthVideoJson, NumberOverflowInTheManifestIsARefusal) {
  test::TempDir dir;
  SynthOptions o;
  o.frames = 2;
  o.width = 16;
  o.height = 12;
  const fs::path v = dir.path() / "v";
  write_depth_video(synthesize(o), v);
  std::string text = test::slurp(v / "manifest.json");
  const auto fps = text.find("\"fps\":");
  ASSERT_NE(fps, std::string::npos);
  text.insert(fps + 6, "1E400, \"fps_was\":");  // "fps":1E400, "fps_was":<the old value>
  test::spit(v / "manifest.json", text);
  try {
    DepthVideoReader r(v);
    ADD_FAILURE() << "opened a manifest with fps 1E400";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::unsupported_format);
    EXPECT_EQ(e.param(), "manifest");
    EXPECT_EQ(std::string(e.what()),
              (v / "manifest.json").string() +
                  ": not valid JSON ([json.exception.out_of_range.406] number overflow parsing '1E400')");
  }
}

}  // namespace
}  // namespace trailscope::tof
