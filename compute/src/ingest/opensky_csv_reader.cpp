// OpenSky state_vectors_data4 CSV. This is the bulk format (an OpenSky day is ~10^8 rows), so the row loop
// splits fields in place, parses numbers with std::from_chars and allocates nothing per accepted row.
#include <cstring>

#include "ingest/detail.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::ingest::detail {
namespace {

enum Role : std::uint8_t {
  kTime,
  kIcao24,
  kLat,
  kLon,
  kVelocity,
  kHeading,
  kVertrate,
  kCallsign,
  kOnground,
  kBaroAltitude,
  kGeoAltitude,
  kRoles,
  kIgnore = 255,
};
constexpr const char* kRoleNames[kRoles] = {"time",     "icao24",       "lat",        "lon",
                                            "velocity", "heading",      "vertrate",   "callsign",
                                            "onground", "baroaltitude", "geoaltitude"};

// true/false as Trino, pandas (True/False) and ClickHouse (1/0) write them; unknown → airborne.
enum class Bool { yes, no, bad };
Bool parse_bool(std::string_view s) {
  s = trim(s);
  if (is_null_token(s)) return Bool::no;
  switch (s.size()) {
    case 1:
      if (s[0] == '1' || s[0] == 't' || s[0] == 'T') return Bool::yes;
      if (s[0] == '0' || s[0] == 'f' || s[0] == 'F') return Bool::no;
      return Bool::bad;
    case 4:
      if (s == "true" || s == "True" || s == "TRUE") return Bool::yes;
      return Bool::bad;
    case 5:
      if (s == "false" || s == "False" || s == "FALSE") return Bool::no;
      return Bool::bad;
    default:
      return Bool::bad;
  }
}

std::string bad_number(Role r, std::string_view v) {
  return std::string("bad number in column '") + kRoleNames[r] + "': " + quote(v);
}

}  // namespace

void read_opensky_csv(ReadContext& ctx) {
  ctx.src.start(/*line_aligned=*/true);
  std::string_view block = ctx.src.next();
  std::size_t pos = 0, line_no = 0;
  // Next line of the stream (without "\r\n"), or false at the end.
  auto next_line = [&](std::string_view& line) {
    while (pos >= block.size()) {
      block = ctx.src.next();
      pos = 0;
      if (block.empty()) return false;
    }
    const char* start = block.data() + pos;
    const std::size_t left = block.size() - pos;
    const void* nl = std::memchr(start, '\n', left);
    const std::size_t len = nl ? static_cast<const char*>(nl) - start : left;
    pos += nl ? len + 1 : len;
    line = std::string_view(start, len);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    ++line_no;
    return true;
  };

  // Header: the first non-blank line.
  std::string_view line;
  do {
    if (!next_line(line))
      throw Error(Error::Kind::unprocessable, "file", "the file is empty: no CSV header and no rows");
  } while (trim(line).empty());
  const std::vector<std::string> names = csv_header_names(line);
  std::vector<std::uint8_t> roles(names.size(), kIgnore);
  bool seen[kRoles] = {};
  for (std::size_t c = 0; c < names.size(); ++c)
    for (int r = 0; r < kRoles; ++r)
      if (!seen[r] && names[c] == kRoleNames[r]) {
        roles[c] = static_cast<std::uint8_t>(r);
        seen[r] = true;
      }
  {
    std::string missing;
    for (Role r : {kTime, kIcao24, kLat, kLon})
      if (!seen[r]) missing += std::string(missing.empty() ? "" : ", ") + kRoleNames[r];
    if (!missing.empty())
      throw Error(Error::Kind::unsupported_format, "format",
                  "not an OpenSky state_vectors_data4 CSV: the header " + quote(line, 80) + " lacks " +
                      missing + " (needs time, icao24, lat, lon)");
  }
  const std::size_t ncols = names.size();
  const std::uint8_t* role = roles.data();

  std::string_view f[kRoles];
  while (next_line(line)) {
    if (line.empty() || trim(line).empty()) continue;  // blank lines are not rows
    ctx.row();
    for (auto& v : f) v = {};
    // Split in place. Quoted fields (a `serials` array "[1,2]") may contain commas.
    const char* p = line.data();
    const char* const e = p + line.size();
    std::size_t col = 0;
    for (;;) {
      const char *fs, *fe, *next;
      if (p < e && *p == '"') {
        fs = p + 1;
        const char* q = fs;
        for (;;) {
          q = static_cast<const char*>(std::memchr(q, '"', e - q));
          if (!q) {
            q = e;
            break;
          }
          if (q + 1 < e && q[1] == '"') {
            q += 2;
            continue;
          }
          break;
        }
        fe = q;
        next = q < e ? static_cast<const char*>(std::memchr(q, ',', e - q)) : nullptr;
        if (!next) next = e;
      } else {
        const void* c = std::memchr(p, ',', e - p);
        fs = p;
        fe = c ? static_cast<const char*>(c) : e;
        next = fe;
      }
      if (col < ncols && role[col] != kIgnore) f[role[col]] = std::string_view(fs, fe - fs);
      ++col;
      if (next >= e) break;
      p = next + 1;
    }
    if (col != ncols) {
      ctx.reject(line_no, [&] {
        return "row has " + std::to_string(col) + " fields, the header has " + std::to_string(ncols);
      });
      continue;
    }

    Sample s;
    if (const Num n = parse_number(f[kTime], s.t); n != Num::ok) {
      if (n == Num::null)
        ctx.reject(line_no, [] { return "time missing"; });
      else
        ctx.reject(line_no, [&] { return bad_number(kTime, f[kTime]); });
      continue;
    }
    const std::string_view icao = trim(f[kIcao24]);
    if (!is_icao24(icao)) {
      ctx.reject(line_no, [&] { return "bad icao24 " + quote(icao) + " (expected 6 hex digits)"; });
      continue;
    }
    const Num nlat = parse_number(f[kLat], s.lat), nlon = parse_number(f[kLon], s.lon);
    if (nlat == Num::bad || nlon == Num::bad) {
      const Role r = nlat == Num::bad ? kLat : kLon;
      ctx.reject(line_no, [&] { return bad_number(r, f[r]); });
      continue;
    }
    if (nlat == Num::null || nlon == Num::null) {
      ctx.reject(line_no, [] { return "missing position (lat/lon empty)"; });
      continue;
    }
    // Optional numeric columns: empty/null → NaN (Sample's default), malformed → reject.
    bool ok = true;
    for (Role r : {kVelocity, kHeading, kVertrate, kBaroAltitude}) {
      float v;
      const Num n = parse_number(f[r], v);
      if (n == Num::bad) {
        ctx.reject(line_no, [&] { return bad_number(r, f[r]); });
        ok = false;
        break;
      }
      if (n == Num::null) continue;
      switch (r) {
        case kVelocity:
          s.speed = v;
          break;
        case kHeading:
          s.track = v;
          break;
        case kVertrate:
          s.vrate = v;
          break;
        default:
          s.alt = v;
          break;
      }
    }
    if (!ok) continue;
    if (std::isnan(s.alt) && !f[kGeoAltitude].empty()) {
      if (parse_number(f[kGeoAltitude], s.alt) == Num::bad) {
        ctx.reject(line_no, [&] { return bad_number(kGeoAltitude, f[kGeoAltitude]); });
        continue;
      }
    }
    const Bool g = parse_bool(f[kOnground]);
    if (g == Bool::bad) {
      ctx.reject(line_no, [&] { return "bad boolean in column 'onground': " + quote(f[kOnground]); });
      continue;
    }
    s.on_ground = g == Bool::yes;
    std::string_view callsign = trim(f[kCallsign]);
    if (is_null_token(callsign)) callsign = {};
    ctx.accept(line_no, icao, callsign, s);
  }
}

}  // namespace trailscope::ingest::detail
