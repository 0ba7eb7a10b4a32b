// The replay control messages without a socket (server/src/replay/replay_control.hpp): every op's effect
// on a viewer's playback state, worked out here by hand for a 10-frame video, and every refusal with its
// exact error message and the state left as it was. tests/server/replay_test.cpp drives the same messages
// through the real server.
#include <gtest/gtest.h>

#include "replay/replay_control.hpp"

namespace trailscope::server {
namespace {

constexpr std::size_t kFrames = 10;

nlohmann::json error_of(const std::string& param, const std::string& detail) {
  return {{"type", "error"}, {"error", "invalid_argument"}, {"param", param}, {"detail", detail}};
}

TEST(ReplayControl, EachOpMovesTheCursorAsSpecified) {
  ReplayPlayback p;
  EXPECT_FALSE(apply_replay_control(R"({"op": "seek", "frame": 7})", kFrames, p));
  EXPECT_EQ(p.cursor, 7u);
  EXPECT_EQ(p.want, 7u);
  EXPECT_FALSE(p.playing);

  EXPECT_FALSE(apply_replay_control(R"({"op": "play"})", kFrames, p));
  EXPECT_TRUE(p.playing);
  EXPECT_EQ(p.cursor, 7u);  // not at the end: play continues from the cursor

  EXPECT_FALSE(apply_replay_control(R"({"op": "step", "delta": 100})", kFrames, p));
  EXPECT_EQ(p.cursor, 9u);  // clamped to the last frame
  EXPECT_FALSE(p.playing);  // stepping pauses
  EXPECT_FALSE(apply_replay_control(R"({"op": "play"})", kFrames, p));
  EXPECT_EQ(p.cursor, 0u);  // play at the last frame starts over
  EXPECT_EQ(p.want, 0u);
  EXPECT_TRUE(p.playing);

  EXPECT_FALSE(apply_replay_control(R"({"op": "step", "delta": -3})", kFrames, p));
  EXPECT_EQ(p.cursor, 0u);  // clamped to the first frame
  EXPECT_FALSE(apply_replay_control(R"({"op": "step", "delta": 4.0})", kFrames, p));
  EXPECT_EQ(p.cursor, 4u);  // a whole number written as a float is an integer

  EXPECT_FALSE(apply_replay_control(R"({"op": "speed", "value": 0.1})", kFrames, p));
  EXPECT_EQ(p.speed, 0.1);
  EXPECT_FALSE(apply_replay_control(R"({"op": "speed", "value": 16})", kFrames, p));
  EXPECT_EQ(p.speed, 16);
  EXPECT_FALSE(apply_replay_control(R"({"op": "play"})", kFrames, p));
  EXPECT_FALSE(apply_replay_control(R"({"op": "pause"})", kFrames, p));
  EXPECT_FALSE(p.playing);
  EXPECT_EQ(p.cursor, 4u);
}

TEST(ReplayControl, RefusalsNameTheFieldAndChangeNothing) {
  const std::string no_op =
      "a message must be a JSON object with a string \"op\": play, pause, seek, step or speed";
  const std::vector<std::pair<std::string, nlohmann::json>> cases = {
      {"", error_of("op", no_op)},
      {"[1, 2]", error_of("op", no_op)},
      {R"({"op": 3})", error_of("op", no_op)},
      {R"({"op": "rewind"})", error_of("op", "unknown op 'rewind': play, pause, seek, step or speed")},
      {R"({"op": "seek", "frame": 10})", error_of("frame", "seek: frame must be an integer in 0..9")},
      {R"({"op": "seek", "frame": -1})", error_of("frame", "seek: frame must be an integer in 0..9")},
      {R"({"op": "seek", "frame": 2.5})", error_of("frame", "seek: frame must be an integer in 0..9")},
      {R"({"op": "seek", "frame": 1e300})", error_of("frame", "seek: frame must be an integer in 0..9")},
      {R"({"op": "step"})", error_of("delta", "step: delta must be an integer (frames, negative = back)")},
      {R"({"op": "step", "delta": "1"})",
       error_of("delta", "step: delta must be an integer (frames, negative = back)")},
      {R"({"op": "speed", "value": 0.09})",
       error_of("value", "speed: value must be a number in 0.1..16 (times the video's rate)")},
      {R"({"op": "speed", "value": 16.5})",
       error_of("value", "speed: value must be a number in 0.1..16 (times the video's rate)")},
      {R"({"op": "speed"})",
       error_of("value", "speed: value must be a number in 0.1..16 (times the video's rate)")},
  };
  for (const auto& [msg, want] : cases) {
    ReplayPlayback p;
    p.cursor = 3;
    p.want = 3;
    p.speed = 2;
    p.playing = true;
    p.anchored = true;
    const auto err = apply_replay_control(msg, kFrames, p);
    ASSERT_TRUE(err) << msg;
    EXPECT_EQ(*err, want) << msg;
    EXPECT_EQ(p.cursor, 3u) << msg;
    EXPECT_EQ(p.want, 3u) << msg;
    EXPECT_EQ(p.speed, 2) << msg;
    EXPECT_TRUE(p.playing) << msg;
    EXPECT_TRUE(p.anchored) << msg;
  }
}

}  // namespace
}  // namespace trailscope::server
