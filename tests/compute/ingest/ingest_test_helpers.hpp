#pragma once
// Small helpers shared by the ingest tests: whole-file gzip read/write and "expect this Error".
#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <string>

#include "test_support.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/trails/trail_set.hpp"

namespace trailscope::test {

/// Whole content of a plain or gzip file (zlib reads both).
inline std::string read_all(const std::filesystem::path& path) {
  gzFile gz = gzopen(path.c_str(), "rb");
  if (!gz) throw std::runtime_error("cannot open " + path.string());
  std::string out;
  char buf[1 << 16];
  int n;
  while ((n = gzread(gz, buf, sizeof buf)) > 0) out.append(buf, n);
  gzclose(gz);
  return out;
}

/// The bytes of a file as they are on disk.
inline std::string read_raw(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

inline void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

inline void write_gz(const std::filesystem::path& path, const std::string& text) {
  gzFile gz = gzopen(path.c_str(), "wb");
  gzwrite(gz, text.data(), static_cast<unsigned>(text.size()));
  gzclose(gz);
}

/// Runs f and returns the trailscope::Error it throws; fails the test when it throws nothing.
inline std::optional<Error> catch_error(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "expected a trailscope::Error";
  return std::nullopt;
}

/// Bitwise equality of two floats, NaN equal to NaN.
inline bool same(float a, float b) {
  return std::memcmp(&a, &b, sizeof a) == 0 || (std::isnan(a) && std::isnan(b));
}

/// Two TrailSets hold the same flights and bit-identical points.
inline void expect_same_trails(const TrailSet& a, const TrailSet& b) {
  ASSERT_EQ(a.num_flights(), b.num_flights());
  ASSERT_EQ(a.num_points(), b.num_points());
  for (std::size_t i = 0; i < a.num_flights(); ++i) {
    const Flight &x = a.flights()[i], &y = b.flights()[i];
    ASSERT_EQ(x.icao24, y.icao24) << i;
    ASSERT_EQ(x.callsign, y.callsign) << i;
    ASSERT_EQ(x.begin, y.begin) << i;
    ASSERT_EQ(x.end, y.end) << i;
  }
  const PointColumns &p = a.points(), &q = b.points();
  for (std::size_t i = 0; i < a.num_points(); ++i) {
    ASSERT_EQ(p.t[i], q.t[i]) << i;
    ASSERT_TRUE(same(p.lat[i], q.lat[i]) && same(p.lon[i], q.lon[i])) << i;
    ASSERT_TRUE(same(p.alt[i], q.alt[i])) << i << ": " << p.alt[i] << " vs " << q.alt[i];
    ASSERT_TRUE(same(p.speed[i], q.speed[i]) && same(p.track[i], q.track[i]) && same(p.vrate[i], q.vrate[i]))
        << i;
    ASSERT_EQ(p.on_ground[i], q.on_ground[i]) << i;
  }
}

}  // namespace trailscope::test
