#pragma once
// The segments of an SO6 file (gzip), read directly from the text with no code of compute/ingest, for
// tests that check the store's flights against the file itself. SO6 (Eurocontrol DDR2 "m3" trajectories):
// one row per segment, whitespace-separated: segment id, ADEP, ADES, aircraft type, begin and end time
// (HHMMSS), begin and end flight level, status, callsign, begin and end date (YYMMDD), begin and end
// latitude and longitude (minutes of a degree), flight id, ...
#include <zlib.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace trailscope::test {

struct So6Segment {
  std::string flight_id, callsign;
  double t_begin, t_end;          ///< Unix seconds
  double lat_begin, lon_begin;    ///< degrees
  double lat_end, lon_end;        ///< degrees
  double alt_begin_m, alt_end_m;  ///< flight level × 100 ft, in metres
};

/// Every segment of the file, in file order. `day_start` is the Unix time of 00:00 UTC of the file's
/// day: the Europe day's rows are all dated 180101, so times are day_start + HHMMSS.
inline std::vector<So6Segment> read_so6_segments(const std::filesystem::path& gz, double day_start) {
  gzFile f = gzopen(gz.c_str(), "rb");
  EXPECT_NE(f, nullptr) << gz;
  std::string text;
  char buf[1 << 16];
  for (int n; f && (n = gzread(f, buf, sizeof buf)) > 0;) text.append(buf, n);
  if (f) gzclose(f);
  const auto seconds = [day_start](const std::string& hhmmss) {
    const int v = std::stoi(hhmmss);
    return day_start + (v / 10000) * 3600 + (v / 100 % 100) * 60 + v % 100;
  };
  std::vector<So6Segment> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::istringstream ls(line);
    std::string seg, adep, ades, type, hb, he, flb, fle, status, cs, db, de, latb, lonb, late, lone, fid;
    ls >> seg >> adep >> ades >> type >> hb >> he >> flb >> fle >> status >> cs >> db >> de >> latb >> lonb >>
        late >> lone >> fid;
    if (fid.empty()) continue;
    out.push_back({fid, cs, seconds(hb), seconds(he), std::stod(latb) / 60, std::stod(lonb) / 60,
                   std::stod(late) / 60, std::stod(lone) / 60, std::stod(flb) * 30.48,
                   std::stod(fle) * 30.48});
  }
  return out;
}

}  // namespace trailscope::test
