// Format names, content detection on every real sample, and clear errors for inputs that are not trails.
#include <gtest/gtest.h>

#include "ingest_test_helpers.hpp"
#include "trailscope/ingest/format.hpp"
#include "trailscope/ingest/ingest.hpp"

namespace trailscope::ingest {
namespace {

using test::catch_error;
using test::shared_data;
using test::TempDir;
using test::write_text;

TEST(Format, NamesRoundTrip) {
  for (Format f : {Format::opensky_csv, Format::traffic_json, Format::so6, Format::readsb_trace})
    EXPECT_EQ(parse_format(to_string(f)), f);
}

TEST(Format, UnknownNameNamesTheParameter) {
  const auto e = catch_error([] { parse_format("csv", "fmt"); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->kind(), Error::Kind::invalid_argument);
  EXPECT_EQ(e->param(), "fmt");
  EXPECT_NE(std::string(e->what()).find("opensky_csv"), std::string::npos);
}

std::string head_of(const std::string& relative) {
  const std::string all = test::read_all(shared_data(relative));
  return all.substr(0, kDetectHeadBytes);
}

TEST(Format, DetectsEveryRealSample) {
  EXPECT_EQ(detect_format(head_of("flights/traffic_europe_20180101_m3.so6.gz")), Format::so6);
  EXPECT_EQ(detect_format(head_of("flights/traffic_sample_belevingsvlucht.json.gz")), Format::traffic_json);
  EXPECT_EQ(detect_format(head_of("flights/traffic_sample_airbus_tree.json.gz")), Format::traffic_json);
  EXPECT_EQ(detect_format(head_of("flights/traffic_sample_zurich_airport.json.gz")), Format::traffic_json);
  EXPECT_EQ(detect_format(head_of("flights/traffic_sample_trace_full_ac671b.json")), Format::readsb_trace);
}

TEST(Format, DetectsOpenSkyHeadersInAnyOrderWithExtras) {
  EXPECT_EQ(detect_format("time,icao24,lat,lon,velocity,heading,vertrate,callsign,onground,alert,spi,squawk,"
                          "baroaltitude,geoaltitude,lastposupdate,lastcontact\n1,abcdef,1,2,,,,,,,,,,,,\n"),
            Format::opensky_csv);
  EXPECT_EQ(detect_format("\xef\xbb\xbf\"lon\",\"LAT\",serials,icao24,hour,time\r\n"), Format::opensky_csv);
}

TEST(Format, DetectsJsonLinesAndCutHeads) {
  EXPECT_EQ(
      detect_format("{\"timestamp\": 1, \"icao24\": \"abcdef\", \"latitude\": 1, \"longitude\": 2}\n{\"tim"),
      Format::traffic_json);
  // A head cut in the middle of the first record still shows its keys.
  EXPECT_EQ(detect_format("[{\"longitude\":1,\"latitude\":2,\"icao24\":\"abcdef\",\"timestamp\":15,\"alti"),
            Format::traffic_json);
  EXPECT_EQ(detect_format("{\"icao\":\"ac671b\",\"timestamp\":1.5,\"trace\":[[0.0,1,2,"),
            Format::readsb_trace);
}

void expect_unsupported(std::string_view head, const std::string& fragment) {
  const auto e = catch_error([&] { detect_format(head); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->kind(), Error::Kind::unsupported_format);
  EXPECT_EQ(e->param(), "format");
  const std::string msg = e->what();
  EXPECT_NE(msg.find(fragment), std::string::npos) << msg;
  EXPECT_NE(msg.find("supported formats"), std::string::npos) << msg;
}

TEST(Format, RejectsWhatIsNotTrailData) {
  using namespace std::string_view_literals;
  expect_unsupported("", "empty");
  expect_unsupported(" \n\n", "blank");
  expect_unsupported("\x89PNG\r\n\x1a\n\0\0\0\rIHDR"sv, "PNG image");
  expect_unsupported("PK\x03\x04\x14\0\0\0"sv, "ZIP");
  expect_unsupported("\x01\x02\x03\0\x04garbage"sv, "binary data");
  expect_unsupported("Lorem ipsum dolor sit amet\nconsectetur\n", "neither a CSV header nor an SO6 segment");
  expect_unsupported("a,b,c\n1,2,3\n", "without the OpenSky column(s) time, icao24, lat, lon");
  expect_unsupported("timestamp,icao24,latitude,longitude\n", "lat, lon");
  expect_unsupported("[{\"x\": 1, \"y\": 2}]", "first record has the keys [x, y]");
  expect_unsupported("[1, 2, 3]", "first element is not an object");
  expect_unsupported("{\"type\": \"FeatureCollection\", \"features\": []}", "keys [type, features]");
  // 20 fields, but not SO6 times.
  expect_unsupported("a b c d e f g h i j k l m n o p q r s t\n", "bad begin time");
}

// ingest_file() on broken inputs: never a crash, always the right kind and a message naming the problem.
TEST(Format, IngestOfBadFilesThrowsClearErrors) {
  TempDir dir;
  const auto path = [&](const char* name) { return (dir.path() / name).string(); };
  auto expect = [](const std::string& file, Error::Kind kind, const std::string& param,
                   const std::string& fragment) {
    const auto e = catch_error([&] { ingest_file(file); });
    ASSERT_TRUE(e) << file;
    EXPECT_EQ(e->kind(), kind) << file << ": " << e->what();
    EXPECT_EQ(e->param(), param) << file;
    EXPECT_NE(std::string(e->what()).find(fragment), std::string::npos) << e->what();
  };

  expect(path("missing.csv"), Error::Kind::not_found, "path", "no such file");
  expect(dir.path().string(), Error::Kind::internal, "path", "directory");

  write_text(path("empty.csv"), "");
  expect(path("empty.csv"), Error::Kind::unsupported_format, "format", "empty");
  test::write_gz(path("empty.gz"), "");
  expect(path("empty.gz"), Error::Kind::unsupported_format, "format", "empty");

  write_text(path("image.png"), std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR\0\0\0\x10", 20));
  expect(path("image.png"), Error::Kind::unsupported_format, "format", "PNG");

  write_text(path("wrong.csv"), "when,who,where\n1,2,3\n");
  expect(path("wrong.csv"), Error::Kind::unsupported_format, "format", "time, icao24, lat, lon");

  write_text(path("text.txt"), "hello world\n");
  expect(path("text.txt"), Error::Kind::unsupported_format, "format", "hello world");

  // A gzip cut in half: the head decompresses, the rest does not.
  const std::string gz = test::read_raw(shared_data("flights/traffic_sample_belevingsvlucht.json.gz"));
  write_text(path("cut.json.gz"), gz.substr(0, gz.size() / 2));
  expect(path("cut.json.gz"), Error::Kind::unprocessable, "file", "truncated");
  // Cut within the gzip header: nothing decompresses at all.
  write_text(path("stub.gz"), gz.substr(0, 5));
  const auto e = catch_error([&] { ingest_file(path("stub.gz")); });
  ASSERT_TRUE(e);
  EXPECT_TRUE(e->kind() == Error::Kind::unprocessable || e->kind() == Error::Kind::unsupported_format)
      << e->what();

  // Corrupt deflate data after a valid start.
  std::string corrupt = gz;
  for (std::size_t i = corrupt.size() / 3; i < corrupt.size() / 3 + 64; ++i)
    corrupt[i] = static_cast<char>(corrupt[i] ^ 0x5a);
  write_text(path("corrupt.json.gz"), corrupt);
  const auto c = catch_error([&] { ingest_file(path("corrupt.json.gz")); });
  ASSERT_TRUE(c);
  EXPECT_EQ(c->kind(), Error::Kind::unprocessable) << c->what();

  // Forcing a format that does not fit.
  IngestOptions force;
  force.format = Format::opensky_csv;
  const auto f = catch_error(
      [&] { ingest_file(shared_data("flights/traffic_sample_trace_full_ac671b.json").string(), force); });
  ASSERT_TRUE(f);
  EXPECT_EQ(f->kind(), Error::Kind::unsupported_format);

  IngestOptions bad_gap;
  bad_gap.gap_seconds = 0;
  const auto g = catch_error([&] { ingest_file(path("wrong.csv"), bad_gap); });
  ASSERT_TRUE(g);
  EXPECT_EQ(g->kind(), Error::Kind::invalid_argument);
  EXPECT_EQ(g->param(), "gap_seconds");
}

}  // namespace
}  // namespace trailscope::ingest
