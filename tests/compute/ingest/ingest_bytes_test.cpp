// ingest_bytes(): the same flights, report and errors as ingest_file() on the same content, plain and gzip,
// and the gzip stream read the way zlib's gzread() reads a file (members concatenated, trailing bytes after
// a member ignored, a cut stream refused).
#include <zlib.h>

#include "ingest_test_helpers.hpp"
#include "trailscope/ingest/ingest.hpp"

namespace trailscope::ingest {
namespace {

using test::catch_error;
using test::expect_same_trails;
using test::shared_data;
using test::TempDir;

// One gzip member of `text` (zlib's deflate with a gzip wrapper, independent of the reader's inflate).
std::string gzip(const std::string& text) {
  z_stream zs{};
  if (deflateInit2(&zs, 6, Z_DEFLATED, 16 + MAX_WBITS, 8, Z_DEFAULT_STRATEGY) != Z_OK) std::abort();
  std::string out(deflateBound(&zs, text.size()) + 64, '\0');
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(text.data()));
  zs.avail_in = static_cast<uInt>(text.size());
  zs.next_out = reinterpret_cast<Bytef*>(out.data());
  zs.avail_out = static_cast<uInt>(out.size());
  if (deflate(&zs, Z_FINISH) != Z_STREAM_END) std::abort();
  out.resize(zs.total_out);
  deflateEnd(&zs);
  return out;
}

void expect_same_report(const IngestReport& a, const IngestReport& b) {
  EXPECT_EQ(a.format, b.format);
  EXPECT_EQ(a.rows, b.rows);
  EXPECT_EQ(a.accepted, b.accepted);
  EXPECT_EQ(a.rejected, b.rejected);
  EXPECT_EQ(a.duplicates, b.duplicates);
  EXPECT_EQ(a.flights, b.flights);
  EXPECT_EQ(a.points, b.points);
  ASSERT_EQ(a.rejects.size(), b.rejects.size());
  for (std::size_t i = 0; i < a.rejects.size(); ++i) {
    EXPECT_EQ(a.rejects[i].line, b.rejects[i].line);
    EXPECT_EQ(a.rejects[i].reason, b.rejects[i].reason);
  }
}

// Every real sample, as its bytes on disk (gzip or plain) and decompressed: the flights of the file.
TEST(IngestBytes, SameFlightsAsTheFileForEveryRealSample) {
  for (const char* name :
       {"flights/traffic_sample_belevingsvlucht.json.gz", "flights/traffic_sample_zurich_airport.json.gz",
        "flights/traffic_sample_trace_full_ac671b.json"}) {
    SCOPED_TRACE(name);
    IngestReport rf, rr, rp;
    const TrailSet from_file = ingest_file(shared_data(name).string(), {}, &rf);
    const std::string raw = test::read_raw(shared_data(name));
    const TrailSet from_raw = ingest_bytes(raw, name, {}, &rr);
    expect_same_trails(from_file, from_raw);
    expect_same_report(rf, rr);
    const std::string plain = test::read_all(shared_data(name));
    const TrailSet from_plain = ingest_bytes(plain, name, {}, &rp);
    expect_same_trails(from_file, from_plain);
    expect_same_report(rf, rp);
  }
}

// The first 100,000 segment lines of the Europe SO6 day (several of a file's 4 MiB blocks, so lines are
// carried across block ends there; one block in memory), plain and gzip.
TEST(IngestBytes, So6LinesAcrossBlocksAsTheFile) {
  const std::string all = test::read_all(shared_data("flights/traffic_europe_20180101_m3.so6.gz"));
  std::size_t cut = 0;
  for (int i = 0; i < 100000 && cut != std::string::npos; ++i) cut = all.find('\n', cut + 1);
  ASSERT_NE(cut, std::string::npos);
  const std::string text = all.substr(0, cut + 1);
  ASSERT_GT(text.size(), 8u << 20);
  TempDir dir;
  test::write_text(dir.path() / "cut.so6", text);
  IngestReport rf, rb, rg;
  const TrailSet from_file = ingest_file((dir.path() / "cut.so6").string(), {}, &rf);
  EXPECT_EQ(rf.rows, 100000u);
  expect_same_trails(from_file, ingest_bytes(text, "cut.so6", {}, &rb));
  expect_same_report(rf, rb);
  expect_same_trails(from_file, ingest_bytes(gzip(text), "cut.so6.gz", {}, &rg));
  expect_same_report(rf, rg);
}

// Two gzip members read as one stream; bytes after the last member that are not a gzip header are ignored
// (as gzread does); the same through a file.
TEST(IngestBytes, ConcatenatedMembersAndTrailingBytes) {
  const std::string head = "time,icao24,lat,lon\n1500000000,abc123,50.0,4.0\n";
  const std::string tail = "1500000010,abc123,50.1,4.1\n1500000020,abc123,50.2,4.2\n";
  const std::string two = gzip(head) + gzip(tail);
  IngestReport r1, r2, r3;
  const TrailSet plain = ingest_bytes(head + tail, "plain.csv", {}, &r1);
  EXPECT_EQ(r1.rows, 3u);
  EXPECT_EQ(plain.num_points(), 3u);
  expect_same_trails(plain, ingest_bytes(two, "two.csv.gz", {}, &r2));
  expect_same_report(r1, r2);
  expect_same_trails(plain, ingest_bytes(two + "trailing bytes, not gzip", "junk.csv.gz", {}, &r3));
  expect_same_report(r1, r3);
  TempDir dir;
  test::write_text(dir.path() / "two.csv.gz", two + "trailing bytes, not gzip");
  expect_same_trails(plain, ingest_file((dir.path() / "two.csv.gz").string()));
}

// The errors: the name stands where the path would be; a cut gzip stream and corrupt deflate data.
TEST(IngestBytes, ErrorsNameTheInput) {
  const auto e = catch_error([] { ingest_bytes("time,icao24,lat,lon\n", "upload.csv"); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->kind(), Error::Kind::unprocessable);
  EXPECT_EQ(e->param(), "file");
  EXPECT_STREQ(e->what(), "no data rows in 'upload.csv' (read as opensky_csv)");

  const auto empty = catch_error([] { ingest_bytes("", "nothing"); });
  ASSERT_TRUE(empty);
  EXPECT_EQ(empty->kind(), Error::Kind::unsupported_format);

  std::string text = "time,icao24,lat,lon\n";
  for (int i = 0; i < 20000; ++i) text += std::to_string(1500000000 + i) + ",abc123,50.0,4.0\n";
  const std::string gz = gzip(text);
  const std::string cut = gz.substr(0, gz.size() / 2);
  const auto t = catch_error([&] { ingest_bytes(cut, "cut.csv.gz"); });
  ASSERT_TRUE(t);
  EXPECT_EQ(t->kind(), Error::Kind::unprocessable);
  EXPECT_EQ(t->param(), "file");
  EXPECT_EQ(std::string(t->what()), "the gzip stream is truncated (unexpected end of file) after " +
                                        std::to_string(cut.size()) + " compressed bytes of 'cut.csv.gz'");
  // The same file on disk gives the same error, with its path.
  TempDir dir;
  const std::string path = (dir.path() / "cut.csv.gz").string();
  test::write_text(path, cut);
  const auto tf = catch_error([&] { ingest_file(path); });
  ASSERT_TRUE(tf);
  EXPECT_EQ(std::string(tf->what()), "the gzip stream is truncated (unexpected end of file) after " +
                                         std::to_string(cut.size()) + " compressed bytes of '" + path + "'");

  std::string corrupt = gz;
  for (std::size_t i = corrupt.size() / 3; i < corrupt.size() / 3 + 64; ++i)
    corrupt[i] = static_cast<char>(corrupt[i] ^ 0x5a);
  const auto c = catch_error([&] { ingest_bytes(corrupt, "corrupt.csv.gz"); });
  ASSERT_TRUE(c);
  EXPECT_EQ(c->kind(), Error::Kind::unprocessable);
  EXPECT_NE(std::string(c->what()).find("the gzip stream is corrupt ("), std::string::npos) << c->what();
  EXPECT_NE(std::string(c->what()).find("'corrupt.csv.gz'"), std::string::npos) << c->what();
}

}  // namespace
}  // namespace trailscope::ingest
