// OpenSky CSV: column mapping, rejects with their line numbers, gzip, progress and cancellation, and the
// writer round trip.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <string>
#include <vector>

#include "ingest_test_helpers.hpp"
#include "trailscope/ingest/ingest.hpp"
#include "trailscope/ingest/opensky_csv_writer.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::ingest {
namespace {

using test::catch_error;
using test::TempDir;
using test::write_text;

// Columns reordered, `serials` quoted with commas inside, `hour` extra.
constexpr const char* kFixture =
    "icao24,time,lon,lat,baroaltitude,geoaltitude,velocity,heading,vertrate,callsign,onground,serials,hour\n"
    "3c6444,1514764800,8.5,47.4,1000.5,1010,120.25,90,-2.5,DLH4AB  ,false,\"[1,2,3]\",1514764800\n"  // 2 ok
    "3c6444,1514764801,,,1000,1010,120,90,0,DLH4AB,false,\"[1]\",1514764800\n"    // 3 no position
    "3c6444,1514764802,8.5,abc,1000,1010,120,90,0,DLH4AB,false,[],1514764800\n"   // 4 bad number
    "3c6444,1514764803,8.5,95.0,1000,1010,120,90,0,DLH4AB,false,[],1514764800\n"  // 5 lat range
    "3c6444,,8.5,47.4,1000,1010,120,90,0,DLH4AB,false,[],1514764800\n"            // 6 no time
    "xyz,1514764805,8.5,47.4,1000,1010,120,90,0,DLH4AB,false,[],1514764800\n"     // 7 bad icao24
    "\n"                                                                          // 8 blank
    "3C6444,1514764810.5,8.6,47.5,,1200,NaN,360,,DLH4AB,true,[],1514764800\r\n"   // 9 ok, geo alt
    "3c6444,1514764811,8.6,47.5,1000\n"                                           // 10 short row
    "3c6444,1514764812,8.6,47.5,1000,1010,120,90,0,DLH4AB,maybe,[],1514764800\n"  // 11 bad bool
    "4b1805,1514764820,7.5,46.9,-3000,,100,45,1,SWR12,0,[],1514764800\n";         // 12 alt range

TEST(OpenSkyCsv, MapsColumnsAndRejectsBadRowsWithTheirLines) {
  TempDir dir;
  const auto file = dir.path() / "states.csv";
  write_text(file, kFixture);
  IngestReport rep;
  const TrailSet set = ingest_file(file.string(), {}, &rep);
  EXPECT_EQ(rep.format, Format::opensky_csv);
  EXPECT_EQ(rep.rows, 10u);  // the blank line is not a row
  EXPECT_EQ(rep.accepted, 2u);
  EXPECT_EQ(rep.rejected, 8u);
  ASSERT_EQ(rep.rejects.size(), 8u);
  const std::vector<std::pair<std::size_t, std::string>> expected = {
      {3, "missing position"},
      {4, "bad number in column 'lat': 'abc'"},
      {5, "latitude out of range"},
      {6, "time missing"},
      {7, "bad icao24 'xyz'"},
      {10, "row has 5 fields, the header has 13"},
      {11, "bad boolean in column 'onground': 'maybe'"},
      {12, "altitude out of range"},
  };
  std::size_t k = 0;
  for (const auto& [line, fragment] : expected) {
    while (k < rep.rejects.size() && rep.rejects[k].line != line) ++k;
    ASSERT_LT(k, rep.rejects.size()) << "no reject for line " << line;
    EXPECT_NE(rep.rejects[k].reason.find(fragment), std::string::npos)
        << "line " << line << ": " << rep.rejects[k].reason;
  }

  ASSERT_EQ(set.num_flights(), 1u);
  const Flight& f = set.flights()[0];
  EXPECT_EQ(f.icao24, "3c6444");
  EXPECT_EQ(f.callsign, "DLH4AB");
  ASSERT_EQ(f.size(), 2u);
  const PointColumns& p = set.points();
  EXPECT_EQ(p.t[0], 1514764800.0);
  EXPECT_FLOAT_EQ(p.lat[0], 47.4f);
  EXPECT_FLOAT_EQ(p.lon[0], 8.5f);
  EXPECT_FLOAT_EQ(p.alt[0], 1000.5f);  // baroaltitude preferred
  EXPECT_FLOAT_EQ(p.speed[0], 120.25f);
  EXPECT_FLOAT_EQ(p.track[0], 90.0f);
  EXPECT_FLOAT_EQ(p.vrate[0], -2.5f);
  EXPECT_EQ(p.on_ground[0], 0);
  EXPECT_EQ(p.t[1], 1514764810.5);
  EXPECT_FLOAT_EQ(p.alt[1], 1200.0f);   // geoaltitude fallback
  EXPECT_TRUE(std::isnan(p.speed[1]));  // "NaN" means unknown
  EXPECT_FLOAT_EQ(p.track[1], 0.0f);    // 360 → 0
  EXPECT_TRUE(std::isnan(p.vrate[1]));
  EXPECT_EQ(p.on_ground[1], 1);

  const nlohmann::json j = rep.to_json();
  EXPECT_EQ(j["format"], "opensky_csv");
  EXPECT_EQ(j["rows"], 10);
  EXPECT_EQ(j["rejects"].size(), 8u);
  EXPECT_EQ(j["rejects"][0]["line"], 3);
}

TEST(OpenSkyCsv, GzipReadsTheSameAsPlain) {
  TempDir dir;
  write_text(dir.path() / "a.csv", kFixture);
  test::write_gz(dir.path() / "a.bin", kFixture);  // the name says nothing; the magic bytes do
  IngestReport ra, rb;
  const TrailSet a = ingest_file((dir.path() / "a.csv").string(), {}, &ra);
  const TrailSet b = ingest_file((dir.path() / "a.bin").string(), {}, &rb);
  test::expect_same_trails(a, b);
  EXPECT_EQ(ra.to_json()["rejects"], rb.to_json()["rejects"]);
}

TEST(OpenSkyCsv, ConcatenatedGzipMembersBomAndCrlf) {
  TempDir dir;
  const auto file = dir.path() / "two.csv.gz";
  test::write_gz(dir.path() / "a.gz", "\xef\xbb\xbftime,icao24,lat,lon\r\n1514764800,abcdef,1,2\r\n");
  test::write_gz(dir.path() / "b.gz", "1514764801,abcdef,1.1,2\r\n1514764802,abcdef,1.2,2");
  write_text(file, test::read_raw(dir.path() / "a.gz") + test::read_raw(dir.path() / "b.gz"));
  IngestReport rep;
  const TrailSet set = ingest_file(file.string(), {}, &rep);
  EXPECT_EQ(rep.rows, 3u);
  EXPECT_EQ(rep.rejected, 0u);
  EXPECT_EQ(set.num_points(), 3u);
}

TEST(OpenSkyCsv, NoUsableRowsIsUnprocessable) {
  TempDir dir;
  write_text(dir.path() / "header.csv", "time,icao24,lat,lon\n");
  auto e = catch_error([&] { ingest_file((dir.path() / "header.csv").string()); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->kind(), Error::Kind::unprocessable);
  EXPECT_NE(std::string(e->what()).find("no data rows"), std::string::npos) << e->what();

  write_text(dir.path() / "bad.csv", "time,icao24,lat,lon\n1514764800,abcdef,,\n1514764801,abcdef,91,0\n");
  e = catch_error([&] { ingest_file((dir.path() / "bad.csv").string()); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->kind(), Error::Kind::unprocessable);
  const std::string msg = e->what();
  EXPECT_NE(msg.find("all 2 rows"), std::string::npos) << msg;
  EXPECT_NE(msg.find("line 2: missing position"), std::string::npos) << msg;
  EXPECT_NE(msg.find("line 3: latitude out of range"), std::string::npos) << msg;
}

// A large file built in the test: every 10th row lacks a position.
std::string many_rows(std::size_t n) {
  std::string s = "time,icao24,lat,lon,velocity,heading,vertrate,callsign,onground,baroaltitude\n";
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t ac = i % 50;
    char line[160];
    if (i % 10 == 7)
      std::snprintf(line, sizeof line, "%zu,%06zx,,,200,90,0,TST%zu,false,10000\n", 1514764800 + i / 50,
                    0xa00000 + ac, ac);
    else
      std::snprintf(line, sizeof line, "%zu,%06zx,%.5f,%.5f,200,90,0,TST%zu,false,10000\n",
                    1514764800 + i / 50, 0xa00000 + ac, 40 + ac * 0.1 + i * 1e-6, -100 + i * 1e-5, ac);
    s += line;
  }
  return s;
}

TEST(OpenSkyCsv, ReportsProgressCountsAllRejectsAndKeepsTheFirstThousand) {
  TempDir dir;
  const auto file = dir.path() / "many.csv.gz";
  test::write_gz(file, many_rows(300000));
  std::vector<std::pair<double, std::string>> calls;
  IngestOptions opts;
  opts.progress = [&](double f, std::string_view stage) { calls.emplace_back(f, std::string(stage)); };
  IngestReport rep;
  const TrailSet set = ingest_file(file.string(), opts, &rep);
  EXPECT_EQ(rep.rows, 300000u);
  EXPECT_EQ(rep.rejected, 30000u);
  EXPECT_EQ(rep.rejects.size(), limits::kMaxReportedRejects);
  EXPECT_EQ(rep.rejects.front().line, 9u);  // row i = 7 is line 9
  EXPECT_EQ(set.num_points(), 270000u);
  EXPECT_EQ(set.num_flights(), 45u);  // aircraft 7, 17, 27, 37, 47 only ever have rows without position
  ASSERT_GE(calls.size(), 4u + 2u);   // ≥ 4 "parse" checkpoints (every 65,536 rows) + assemble 0, 1
  double last = 0;
  for (const auto& [f, stage] : calls) {
    if (stage != "parse") continue;
    EXPECT_GE(f, last);
    EXPECT_LE(f, 1.0);
    last = f;
  }
  EXPECT_EQ(calls.back(), (std::pair<double, std::string>{1.0, "assemble"}));
}

TEST(OpenSkyCsv, CancelStopsTheIngest) {
  TempDir dir;
  const auto file = dir.path() / "many.csv";
  write_text(file, many_rows(200000));
  CancelToken token;
  IngestOptions opts;
  opts.cancel = &token;
  opts.progress = [&](double, std::string_view) { token.cancel(); };
  const auto e = catch_error([&] { ingest_file(file.string(), opts); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->kind(), Error::Kind::cancelled);
}

TEST(OpenSkyCsv, LinesLongerThanAReadBlock) {
  // A quoted `serials` field of 6 MB: the reader must grow its block rather than split the line.
  std::string text = "time,icao24,lat,lon,serials\n1514764800,abcdef,1,2,\"[";
  text.append(6u << 20, '7');
  text += "]\"\n1514764801,abcdef,1.5,2,\"[]\"";  // and a last line without a newline
  test::TempDir dir;
  write_text(dir.path() / "long.csv", text);
  IngestReport rep;
  const TrailSet set = ingest_file((dir.path() / "long.csv").string(), {}, &rep);
  EXPECT_EQ(rep.rows, 2u);
  EXPECT_EQ(rep.rejected, 0u);
  ASSERT_EQ(set.num_points(), 2u);
  EXPECT_FLOAT_EQ(set.points().lat[1], 1.5f);
}

TEST(OpenSkyCsv, GapSplitsFlights) {
  TempDir dir;
  write_text(dir.path() / "gap.csv",
             "time,icao24,lat,lon,callsign\n100,abcdef,1,1,X\n200,abcdef,1,1.1,X\n5000,abcdef,1,2,X\n5001,"
             "abcdef,1,2,X\n");
  IngestReport rep;
  EXPECT_EQ(ingest_file((dir.path() / "gap.csv").string(), {}, &rep).num_flights(), 2u);
  EXPECT_EQ(rep.duplicates, 0u);
  IngestOptions wide;
  wide.gap_seconds = 10000;
  EXPECT_EQ(ingest_file((dir.path() / "gap.csv").string(), wide).num_flights(), 1u);
}

TEST(OpenSkyCsv, WriterRoundTripsBitForBit) {
  // Points with awkward values: NaNs, negative altitude, fractional times, on-ground flags.
  TrailSetBuilder b;
  for (int i = 0; i < 500; ++i) {
    Sample s;
    s.t = 1700000000.125 + i * 7.3;
    s.lat = 51.4700222f + i * 1e-4f;
    s.lon = -0.4542955f - i * 1.7e-4f;
    s.alt = i % 17 == 0 ? Sample::kUnknown : -30.5f + i * 11.1f;
    s.speed = i % 5 == 0 ? Sample::kUnknown : 0.1f * i;
    s.track = i % 7 == 0 ? Sample::kUnknown : static_cast<float>(std::fmod(i * 3.3, 360.0));
    s.vrate = i % 3 == 0 ? Sample::kUnknown : -12.34f + i * 0.01f;
    s.on_ground = i < 20;
    b.add(i % 2 ? "4CA7B5" : "400a0e", i % 2 ? "EIN123" : "BAW1", s);
  }
  const TrailSet original = b.build();
  TempDir dir;
  for (bool gz : {false, true}) {
    const auto file = dir.path() / (gz ? "out.csv.gz" : "out.csv");
    write_opensky_csv(original, file.string(), gz);
    EXPECT_FALSE(std::filesystem::exists(file.string() + ".part"));
    const std::string text = test::read_all(file);
    EXPECT_EQ(text.substr(0, text.find('\n')), kOpenSkyCsvHeader);
    IngestReport rep;
    const TrailSet back = ingest_file(file.string(), {}, &rep);
    EXPECT_EQ(rep.rejected, 0u);
    test::expect_same_trails(original, back);
  }
}

TEST(OpenSkyCsv, WriterRefusesFlightsWithoutIcao24) {
  TrailSetBuilder b;
  Sample s;
  s.t = 1514764800, s.lat = 50, s.lon = 5;
  b.add("", "AFR1234", s);
  const TrailSet set = b.build();
  TempDir dir;
  const auto e = catch_error([&] { write_opensky_csv(set, (dir.path() / "x.csv").string(), false); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->kind(), Error::Kind::invalid_argument);
  EXPECT_EQ(e->param(), "dataset");
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "x.csv"));
}

}  // namespace
}  // namespace trailscope::ingest
