// The tracker log format (proto/tracker_log.proto): binary and JSON round trips of every field, the JSON
// of single frames, and the exact errors of damaged or foreign input.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "log_fixture.hpp"
#include "test_support.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"

namespace trailscope::tracker {
namespace {
namespace fs = std::filesystem;
using test::sample_log;

/// Runs `f`, expecting an Error of `kind` naming `param` with exactly `message`.
template <typename F>
void expect_error(F&& f, Error::Kind kind, const std::string& param, const std::string& message) {
  try {
    f();
    ADD_FAILURE() << "no error; expected: " << message;
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), kind) << e.what();
    EXPECT_EQ(e.param(), param);
    EXPECT_EQ(std::string(e.what()), message);
  }
}

std::string json_of(const TrackerLog& log) {
  return encode_log(log, LogEncoding::json);
}
nlohmann::json parsed(const TrackerLog& log) {
  return nlohmann::json::parse(json_of(log));
}
TrackerLog decode_json(const nlohmann::json& j) {
  return decode_log(j.dump());
}

TEST(TrackerLogFormat, BinaryRoundTripKeepsEveryField) {
  for (bool with_truth : {true, false}) {
    const TrackerLog log = sample_log(with_truth);
    const std::string bytes = encode_log(log, LogEncoding::binary);
    ASSERT_FALSE(bytes.empty());
    EXPECT_NE(bytes.front(), '{');
    test::expect_same_log(decode_log(bytes), log);
  }
}

TEST(TrackerLogFormat, JsonRoundTripKeepsEveryField) {
  for (bool with_truth : {true, false}) {
    const TrackerLog log = sample_log(with_truth);
    const std::string text = json_of(log);
    test::expect_same_log(decode_log(text), log);
    // Leading blanks still mean JSON.
    test::expect_same_log(decode_log(" \n\t" + text), log);
  }
}

TEST(TrackerLogFormat, JsonIsTheCanonicalProtobufMapping) {
  const TrackerLog log = sample_log();
  const std::string text = json_of(log);
  EXPECT_EQ(text.find('\n'), std::string::npos) << "JSON is compact";
  const nlohmann::json j = nlohmann::json::parse(text);
  const auto& f1 = j["frames"][1];
  // lowerCamelCase names, enum names, NaN as the string "NaN", zero-valued and empty fields present.
  EXPECT_EQ(f1["timestampS"], 4.04);
  EXPECT_EQ(f1["state"], "STATE_TRACK");
  EXPECT_EQ(j["frames"][0]["state"], "STATE_SEARCH");
  EXPECT_EQ(j["frames"][2]["state"], "STATE_LOST");
  EXPECT_EQ(f1["model"]["pairMm"][4], "NaN");
  EXPECT_EQ(f1["model"]["pairErrorMm"][5], "NaN");
  EXPECT_EQ(f1["candidates"], nlohmann::json::array());
  EXPECT_EQ(f1["teats"][0]["confidence"], 0);
  EXPECT_EQ(f1["teats"][3]["visible"], false);
  EXPECT_EQ(f1["index"], 101) << "frame indices are JSON numbers, not strings";
  EXPECT_EQ(j["frames"][0]["candidates"][0]["templateIndex"], 1);
  EXPECT_EQ(j["header"]["frameCount"], 4);
  EXPECT_EQ(j["header"]["version"], kTrackerLogVersion);
  EXPECT_EQ(j["header"]["intrinsics"]["width"], 176);
  EXPECT_EQ(nlohmann::json::parse(j["header"]["videoSourceJson"].get<std::string>())["seed"],
            18446744073709551557ull);
  EXPECT_EQ(j["truth"][2], (nlohmann::json{{"hasTruth", false}}));
  EXPECT_EQ(j["truth"][0]["hasTruth"], true);
  EXPECT_EQ(j["truth"][0]["value"]["teats"][1]["tipPx"], nlohmann::json::array()) << "no projection";
  EXPECT_FALSE(j["truth"][0]["value"]["teats"][3].contains("boxPx")) << "no box";
  EXPECT_EQ(j["truth"][0]["value"]["teats"][0]["boxPx"]["x"], 80.5);
}

TEST(TrackerLogFormat, FrameAndHeaderJsonEqualTheLogsJson) {
  const TrackerLog log = sample_log();
  const nlohmann::json j = parsed(log);
  ASSERT_EQ(j["frames"].size(), log.frames.size());
  for (std::size_t i = 0; i < log.frames.size(); ++i) {
    // Compared as text: nlohmann's == would call two NaN-free objects equal even if 1 and 1.0 differed.
    EXPECT_EQ(frame_to_json(log.frames[i]).dump(), j["frames"][i].dump()) << "frame " << i;
  }
  EXPECT_EQ(header_to_json(log.header).dump(), j["header"].dump());
}

TEST(TrackerLogFormat, EncodeRefusesInconsistentLogs) {
  TrackerLog log = sample_log();
  log.truth.pop_back();
  expect_error([&] { encode_log(log, LogEncoding::binary); }, Error::Kind::invalid_argument, "log",
               "log: truth has 3 entries for 4 frames");
  log = sample_log();
  log.header.frame_count = 5;
  expect_error([&] { encode_log(log, LogEncoding::json); }, Error::Kind::invalid_argument, "log",
               "log: header.frameCount is 5 but the log has 4 frames");
}

TEST(TrackerLogFormat, ForeignBytesAreUnsupported) {
  expect_error([] { decode_log(""); }, Error::Kind::unsupported_format, "log", "log: empty input");
  expect_error([] { decode_log(" \n "); }, Error::Kind::unsupported_format, "log", "log: empty input");
  expect_error([] { decode_log(std::string("\x07\xff\xff garbage", 11)); }, Error::Kind::unsupported_format,
               "log", "log: neither JSON nor a binary tracker log (or a truncated one)");
  expect_error([] { decode_log("{\"header\": {\"version\": 1"); }, Error::Kind::unsupported_format, "log",
               "log: not JSON text");
  expect_error([] { decode_log("{}"); }, Error::Kind::unsupported_format, "log",
               "log: not a tracker log (no header)");
}

TEST(TrackerLogFormat, TruncatedBinaryIsRefused) {
  const TrackerLog log = sample_log(false);
  const std::string bytes = encode_log(log, LogEncoding::binary);
  // Cut inside the last frame's record: the binary no longer parses.
  expect_error([&] { decode_log(std::string_view(bytes).substr(0, bytes.size() - 1)); },
               Error::Kind::unsupported_format, "log",
               "log: neither JSON nor a binary tracker log (or a truncated one)");
  // Cut exactly before the last frame record: that parses, and the header's frame count catches it. The
  // record's size is the difference between logs of one and two copies of that frame.
  TrackerLog one = log, two = log;
  one.frames = {log.frames[3]};
  one.header.frame_count = 1;
  two.frames = {log.frames[3], log.frames[3]};
  two.header.frame_count = 2;
  const std::size_t record =
      encode_log(two, LogEncoding::binary).size() - encode_log(one, LogEncoding::binary).size();
  expect_error([&] { decode_log(std::string_view(bytes).substr(0, bytes.size() - record)); },
               Error::Kind::invalid_argument, "log", "log: header.frameCount is 4 but the log has 3 frames");
}

TEST(TrackerLogFormat, StructuralFaultsNameFieldAndFrame) {
  const nlohmann::json good = parsed(sample_log());
  auto with = [&](auto edit) {
    nlohmann::json j = good;
    edit(j);
    return [j] { decode_json(j); };
  };
  expect_error(with([](auto& j) { j["frames"][2]["teats"].erase(1); }), Error::Kind::invalid_argument, "log",
               "log: frames[2].teats has 3 entries, expected 4");
  expect_error(
      with([](auto& j) { j["truth"][3]["value"]["teats"].push_back(j["truth"][3]["value"]["teats"][0]); }),
      Error::Kind::invalid_argument, "log", "log: truth[3].value.teats has 5 entries, expected 4");
  expect_error(with([](auto& j) { j["truth"].erase(0); }), Error::Kind::invalid_argument, "log",
               "log: truth has 3 entries for 4 frames");
  expect_error(with([](auto& j) { j["frames"][3]["state"] = 7; }), Error::Kind::invalid_argument, "log",
               "log: frames[3].state is an unknown state (7)");
  expect_error(with([](auto& j) { j["frames"][0].erase("state"); }), Error::Kind::invalid_argument, "log",
               "log: frames[0].state is an unknown state (0)");
  expect_error(with([](auto& j) { j["frames"][1]["model"]["pairMm"].erase(0); }),
               Error::Kind::invalid_argument, "log", "log: frames[1].model.pairMm has 5 values, expected 6");
  expect_error(with([](auto& j) { j["frames"][0]["candidates"][1]["tipMm"].push_back(1.0); }),
               Error::Kind::invalid_argument, "log",
               "log: frames[0].candidates[1].tipMm has 4 values, expected 3");
  expect_error(with([](auto& j) { j["frames"][0]["candidates"][0]["teat"] = 4; }),
               Error::Kind::invalid_argument, "log", "log: frames[0].candidates[0].teat 4 is not -1..3");
  expect_error(with([](auto& j) { j["frames"][2]["candidates"][1]["templateIndex"] = 3; }),
               Error::Kind::invalid_argument, "log",
               "log: frames[2].candidates[1].templateIndex 3 is not in the bank of 3");
  expect_error(with([](auto& j) { j["header"]["version"] = kTrackerLogVersion + 1; }),
               Error::Kind::invalid_argument, "log", "log: version 2 is newer than this reader's 1");
  expect_error(with([](auto& j) { j["header"]["version"] = 0; }), Error::Kind::invalid_argument, "log",
               "log: header.version 0 is not a version");
  expect_error(with([](auto& j) { j["header"]["videoSourceJson"] = "{seed"; }), Error::Kind::invalid_argument,
               "log", "log: header.videoSourceJson is not JSON text");
}

TEST(TrackerLogFormat, JsonThatDoesNotFitTheSchemaIsAStructuralFault) {
  // Valid JSON, but a name the schema lacks (a typo or a newer writer) or an enum name it does not know.
  for (auto edit : {+[](nlohmann::json& j) { j["frames"][0]["stateName"] = "TRACK"; },
                    +[](nlohmann::json& j) { j["frames"][0]["state"] = "STATE_BOGUS"; }}) {
    nlohmann::json j = parsed(sample_log());
    edit(j);
    try {
      decode_json(j);
      ADD_FAILURE() << "accepted " << j["frames"][0].dump();
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), Error::Kind::invalid_argument);
      EXPECT_EQ(e.param(), "log");
      EXPECT_EQ(std::string(e.what()).rfind("log: JSON does not fit the schema: ", 0), 0u) << e.what();
    }
  }
}

TEST(TrackerLogFormat, InputBeyondTheByteLimitIsRefusedBeforeParsing) {
  const std::string huge(limits::kMaxRunBytes + 1, ' ');
  expect_error([&] { decode_log(huge); }, Error::Kind::payload_too_large, "log",
               "log: " + std::to_string(limits::kMaxRunBytes + 1) + " bytes exceed the limit of " +
                   std::to_string(limits::kMaxRunBytes));
}

TEST(TrackerLogFiles, WriteIsAtomicAndRefusesToOverwrite) {
  trailscope::test::TempDir dir;
  const TrackerLog log = sample_log();
  for (const char* name : {"run.tslog", "run.json", "RUN.JSON"}) {
    const fs::path path = dir.path() / name;
    write_log(log, path);
    test::expect_same_log(read_log(path), log);
    std::ifstream in(path, std::ios::binary);
    const char first = static_cast<char>(in.get());
    EXPECT_EQ(first == '{', std::string(name) != "run.tslog") << "encoding follows the extension: " << name;
    expect_error([&] { write_log(log, path); }, Error::Kind::conflict, "output",
                 "output: " + path.string() + " exists");
  }
  // Replacing: an inconsistent log fails before the old file is touched; a good one replaces it.
  const fs::path path = dir.path() / "run.tslog";
  TrackerLog bad = sample_log();
  bad.truth.pop_back();
  EXPECT_THROW(write_log(bad, path, true), Error);
  test::expect_same_log(read_log(path), log);
  TrackerLog other = sample_log(false);
  other.header.run_id = "run-other";
  write_log(other, path, true);
  test::expect_same_log(read_log(path), other);
  // No temporary file is left behind.
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir.path())) {
    ++files;
    EXPECT_NE(e.path().filename().string().front(), '.') << e.path();
  }
  EXPECT_EQ(files, 3u);
}

TEST(TrackerLogFiles, ReadErrorsNameTheFile) {
  trailscope::test::TempDir dir;
  const fs::path missing = dir.path() / "missing.tslog";
  expect_error([&] { read_log(missing); }, Error::Kind::not_found, "log",
               "log: no such file " + missing.string());
  const fs::path junk = dir.path() / "junk.json";
  std::ofstream(junk) << "{\"frames\": [";
  expect_error([&] { read_log(junk); }, Error::Kind::unsupported_format, "log",
               junk.string() + ": log: not JSON text");
  EXPECT_THROW(write_log(sample_log(), dir.path() / "no-such-folder" / "run.tslog"), Error);
}

}  // namespace
}  // namespace trailscope::tracker
