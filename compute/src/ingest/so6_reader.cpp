// Eurocontrol SO6 m3: one flight segment per line. Segments are gathered per flight_id, turned into a
// time-ordered point list, and speed/track/vertical rate are derived from consecutive points, since the
// format carries positions and flight levels only.
#include <GeographicLib/Geodesic.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <unordered_map>

#include "ingest/detail.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::ingest::detail {
namespace {

bool two_digits(const char* p, int& v) {
  if (p[0] < '0' || p[0] > '9' || p[1] < '0' || p[1] > '9') return false;
  v = (p[0] - '0') * 10 + (p[1] - '0');
  return true;
}

// hhmmss → seconds of the day.
bool parse_hhmmss(std::string_view s, int& sec) {
  int h, m, x;
  if (s.size() != 6 || !two_digits(s.data(), h) || !two_digits(s.data() + 2, m) ||
      !two_digits(s.data() + 4, x))
    return false;
  if (h > 23 || m > 59 || x > 59) return false;
  sec = h * 3600 + m * 60 + x;
  return true;
}

// yymmdd → days since 1970-01-01 (yy < 70 → 20yy: SO6 dates from the 1990s on, and Unix time starts 1970).
bool parse_yymmdd(std::string_view s, std::int64_t& days) {
  int y, m, d;
  if (s.size() != 6 || !two_digits(s.data(), y) || !two_digits(s.data() + 2, m) ||
      !two_digits(s.data() + 4, d))
    return false;
  if (m < 1 || m > 12 || d < 1 || d > 31) return false;
  days = days_from_civil(y < 70 ? 2000 + y : 1900 + y, static_cast<unsigned>(m), static_cast<unsigned>(d));
  return true;
}

struct Point {
  double t;
  float lat, lon, alt;
};

struct FlightAcc {
  std::string callsign;
  std::vector<Point> points;
};

}  // namespace

const char* parse_so6_line(std::string_view line, So6Segment& seg) noexcept {
  constexpr std::size_t kFields = 20;
  std::string_view f[kFields];
  std::size_t n = 0, i = 0;
  while (true) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    if (i >= line.size()) break;
    const std::size_t b = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (n == kFields) return "expected 20 space-separated fields, found more";
    f[n++] = line.substr(b, i - b);
  }
  if (n != kFields) return "expected 20 space-separated fields, found fewer";
  int tb, te;
  std::int64_t db, de;
  if (!parse_hhmmss(f[4], tb)) return "bad begin time (hhmmss, field 5)";
  if (!parse_hhmmss(f[5], te)) return "bad end time (hhmmss, field 6)";
  if (!parse_yymmdd(f[10], db)) return "bad begin date (yymmdd, field 11)";
  if (!parse_yymmdd(f[11], de)) return "bad end date (yymmdd, field 12)";
  float flb, fle;
  if (parse_number(f[6], flb) != Num::ok) return "bad begin flight level (field 7)";
  if (parse_number(f[7], fle) != Num::ok) return "bad end flight level (field 8)";
  double c[4];
  for (int k = 0; k < 4; ++k)
    if (parse_number(f[12 + k], c[k]) != Num::ok) return "bad coordinate (decimal minutes, fields 13-16)";
  seg.callsign = f[9];
  seg.flight_id = f[16];
  seg.t_begin = static_cast<double>(db * 86400 + tb);
  seg.t_end = static_cast<double>(de * 86400 + te);
  seg.alt_begin = static_cast<float>(flb * 100.0 * kFeet);
  seg.alt_end = static_cast<float>(fle * 100.0 * kFeet);
  seg.lat_begin = c[0] / 60.0, seg.lon_begin = c[1] / 60.0;
  seg.lat_end = c[2] / 60.0, seg.lon_end = c[3] / 60.0;
  return nullptr;
}

void read_so6(ReadContext& ctx) {
  ctx.src.start(/*line_aligned=*/true);
  // flight_id → index into `flights`, which keeps first-seen order so that nothing depends on hashing.
  std::unordered_map<std::string, std::size_t> index;
  std::vector<FlightAcc> flights;
  std::unordered_map<std::string, std::size_t> flights_per_callsign;
  std::string key;
  std::size_t line_no = 0;
  for (std::string_view block = ctx.src.next(); !block.empty(); block = ctx.src.next()) {
    std::size_t pos = 0;
    while (pos < block.size()) {
      const void* nl = std::memchr(block.data() + pos, '\n', block.size() - pos);
      const std::size_t end = nl ? static_cast<const char*>(nl) - block.data() : block.size();
      const std::string_view line = block.substr(pos, end - pos);
      pos = end + 1;
      ++line_no;
      if (trim(line).empty()) continue;
      ctx.row();
      So6Segment seg;
      if (const char* why = parse_so6_line(line, seg)) {
        ctx.reject(line_no, [why] { return why; });
        continue;
      }
      Sample a, b;
      a.t = seg.t_begin, a.lat = static_cast<float>(seg.lat_begin), a.lon = static_cast<float>(seg.lon_begin);
      a.alt = seg.alt_begin;
      b.t = seg.t_end, b.lat = static_cast<float>(seg.lat_end), b.lon = static_cast<float>(seg.lon_end);
      b.alt = seg.alt_end;
      normalise_sample(a), normalise_sample(b);
      const char* why_a = check_sample(a);
      const char* why_b = check_sample(b);
      if (why_a || why_b) {
        ctx.reject(line_no, [&] {
          return std::string(why_a ? "segment begin: " : "segment end: ") + (why_a ? why_a : why_b);
        });
        continue;
      }
      ++ctx.report.accepted;
      key.assign(seg.flight_id);
      auto [it, inserted] = index.try_emplace(key, flights.size());
      if (inserted) {
        flights.push_back(FlightAcc{std::string(seg.callsign), {}});
        ++flights_per_callsign[flights.back().callsign];
      }
      auto& pts = flights[it->second].points;
      pts.push_back({a.t, a.lat, a.lon, a.alt});
      pts.push_back({b.t, b.lat, b.lon, b.alt});
    }
  }
  if (ctx.opts.cancel) ctx.opts.cancel->throw_if_cancelled();

  std::vector<std::string> ids(flights.size());
  for (auto& [id, i] : index) ids[i] = id;
  const GeographicLib::Geodesic& geod = GeographicLib::Geodesic::WGS84();
  constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  // Sorting and the geodesic per leg (most of the time of an SO6 ingest) run per flight in parallel;
  // the builder then takes the samples in flight order, so the result does not depend on threads.
  std::vector<std::vector<Sample>> samples(flights.size());
  std::vector<std::size_t> dups(flights.size(), 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, flights.size(), 64), [&](const auto& range) {
    for (std::size_t fi = range.begin(); fi != range.end(); ++fi) {
      auto& p = flights[fi].points;
      // Order by time; consecutive segments share an endpoint, so drop a point whose time repeats.
      std::stable_sort(p.begin(), p.end(), [](const Point& x, const Point& y) { return x.t < y.t; });
      std::size_t w = 0;
      for (std::size_t r = 0; r < p.size(); ++r) {
        if (w > 0 && p[r].t == p[w - 1].t) {
          const Point& k = p[w - 1];
          if (p[r].lat != k.lat || p[r].lon != k.lon || p[r].alt != k.alt) ++dups[fi];
          continue;
        }
        p[w++] = p[r];
      }
      p.resize(w);
      auto& out = samples[fi];
      out.reserve(p.size());
      for (std::size_t i = 0; i < p.size(); ++i) {
        Sample s;
        s.t = p[i].t, s.lat = p[i].lat, s.lon = p[i].lon, s.alt = p[i].alt;
        if (p.size() > 1) {
          // The leg leaving this point, or for the last point the leg arriving at it.
          const bool last = i + 1 == p.size();
          const Point& a = last ? p[i - 1] : p[i];
          const Point& b = last ? p[i] : p[i + 1];
          double dist, azi1, azi2;
          geod.Inverse(a.lat, a.lon, b.lat, b.lon, dist, azi1, azi2);
          const double dt = b.t - a.t;  // > 0 after the dedup above
          s.speed = static_cast<float>(dist / dt);
          s.track = dist > 1.0 ? static_cast<float>(last ? azi2 : azi1) : kNaN;
          s.vrate = static_cast<float>((b.alt - a.alt) / dt);
          // A leg faster than any aircraft comes from a glitch in the source (a one-point position
          // spike, a clock wrapping at midnight): keep the positions, leave the derived values unknown.
          if (s.speed > kMaxSpeed) s.speed = s.track = kNaN;
          if (std::fabs(s.vrate) > kMaxVerticalRate) s.vrate = kNaN;
        }
        normalise_sample(s);
        out.push_back(s);
      }
      std::vector<Point>().swap(p);
    }
  });
  std::string slot;
  for (std::size_t fi = 0; fi < flights.size(); ++fi) {
    ctx.reader_duplicates += dups[fi];
    const FlightAcc& fl = flights[fi];
    const bool shared = flights_per_callsign[fl.callsign] > 1;
    slot = shared ? fl.callsign + "/" + ids[fi] : fl.callsign;
    for (const Sample& s : samples[fi]) ctx.builder.add("", slot, s);
    std::vector<Sample>().swap(samples[fi]);  // release as we go: the builder now holds a copy
  }
  // flight_id delimits flights; DP-simplified segments often last longer than any sensible gap.
  ctx.gap_seconds = std::numeric_limits<double>::infinity();
}

}  // namespace trailscope::ingest::detail
