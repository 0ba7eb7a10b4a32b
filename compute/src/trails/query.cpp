#include "trailscope/trails/query.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/core/text.hpp"

namespace trailscope {

namespace {
constexpr double kFeetToMetres = 0.3048;

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  std::istringstream in(s);
  while (std::getline(in, cur, sep)) out.push_back(cur);
  if (!s.empty() && s.back() == sep) out.emplace_back();
  return out;
}

std::string trim(const std::string& s) {
  std::size_t b = s.find_first_not_of(" \t"), e = s.find_last_not_of(" \t");
  return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

// Strict number parse: the whole string must be a finite number.
bool to_double(const std::string& text, double& out) {
  const std::string s = trim(text);
  if (s.empty()) return false;
  const char* first = s.data();
  if (*first == '+') ++first;
  auto [p, ec] = std::from_chars(first, s.data() + s.size(), out);
  return ec == std::errc() && p == s.data() + s.size() && std::isfinite(out);
}

double number(const std::string& text, const std::string& param) {
  double v;
  if (!to_double(text, v)) throw invalid_argument(param, param + ": '" + text + "' is not a number");
  return v;
}

bool overlaps_lon(float fmin, float fmax, const BBox& b) {
  if (b.west <= b.east) return fmax >= b.west && fmin <= b.east;
  return fmax >= b.west || fmin <= b.east;  // box crosses 180°
}

// Days since 1970-01-01 of a proleptic Gregorian date (H. Hinnant's days_from_civil).
long long days_from_civil(long long y, unsigned m, unsigned d) {
  y -= m <= 2;
  const long long era = (y >= 0 ? y : y - 399) / 400;
  const unsigned yoe = static_cast<unsigned>(y - era * 400);
  const unsigned doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
  const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + static_cast<long long>(doe) - 719468;
}
}  // namespace

bool callsign_matches(const std::string& pattern, const std::string& cs) {
  if (pattern.find_first_of("*?") == std::string::npos) return cs.compare(0, pattern.size(), pattern) == 0;
  // Glob match with backtracking on the last '*': linear in practice for short callsigns.
  std::size_t p = 0, c = 0, star = std::string::npos, mark = 0;
  while (c < cs.size()) {
    if (p < pattern.size() && (pattern[p] == '?' || pattern[p] == cs[c])) {
      ++p, ++c;
    } else if (p < pattern.size() && pattern[p] == '*') {
      star = p++, mark = c;
    } else if (star != std::string::npos) {
      p = star + 1, c = ++mark;
    } else {
      return false;
    }
  }
  while (p < pattern.size() && pattern[p] == '*') ++p;
  return p == pattern.size();
}

bool Query::matches_flight_ids(const Flight& f) const {
  if (!icao24.empty() && !std::binary_search(icao24.begin(), icao24.end(), f.icao24)) return false;
  if (!callsign.empty() && !callsign_matches(callsign, f.callsign)) return false;
  return true;
}

bool Query::may_match(const Flight& f) const {
  if (t0 && f.t_max < *t0) return false;
  if (t1 && f.t_min >= *t1) return false;
  if (bbox) {
    if (f.lat_max < bbox->south || f.lat_min > bbox->north) return false;
    if (!f.crosses_antimeridian && !overlaps_lon(f.lon_min, f.lon_max, *bbox)) return false;
  }
  if (alt_min || alt_max) {
    if (std::isnan(f.alt_max)) return false;
    if (alt_min && f.alt_max < *alt_min) return false;
    if (alt_max && f.alt_min > *alt_max) return false;
  }
  return matches_flight_ids(f);
}

std::string Query::canonical() const {
  // Numbers in their shortest round-trip text (core/text.hpp): equal queries give equal keys, and
  // distinct values distinct keys.
  std::string s;
  const auto number = [&s](const char* key, double v) {
    s += key;
    append_shortest(s, v);
    s += '&';
  };
  if (bbox) {
    s += "bbox=";
    for (const double v : {bbox->west, bbox->south, bbox->east, bbox->north}) {
      append_shortest(s, v);
      s += ',';
    }
    s.back() = '&';
  }
  if (t0) number("t0=", *t0);
  if (t1) number("t1=", *t1);
  if (alt_min) number("alt_min_m=", *alt_min);
  if (alt_max) number("alt_max_m=", *alt_max);
  if (!icao24.empty()) {
    s += "icao24=";
    for (std::size_t i = 0; i < icao24.size(); ++i) s += (i ? "," : "") + icao24[i];
    s += '&';
  }
  if (!callsign.empty()) s += "callsign=" + callsign + '&';
  if (on_ground) s += std::string("on_ground=") + (*on_ground ? "true" : "false") + '&';
  if (!s.empty()) s.pop_back();
  return s;
}

double parse_time(const std::string& raw, const std::string& param) {
  const std::string text = trim(raw);
  double v;
  if (to_double(text, v)) return v;
  // ISO 8601: YYYY-MM-DD[(T| )hh:mm[:ss[.fff]]][Z|±hh[:]mm]
  int Y, M, D, h = 0, m = 0, consumed = 0;
  double s = 0;
  const auto bad = [&] {
    return invalid_argument(param, param + ": '" + text +
                                       "' is neither Unix seconds nor an ISO 8601 time such as "
                                       "2018-01-01T06:00:00Z");
  };
  if (std::sscanf(text.c_str(), "%4d-%2d-%2d%n", &Y, &M, &D, &consumed) != 3 || consumed != 10) throw bad();
  std::size_t pos = 10;
  if (pos < text.size() && (text[pos] == 'T' || text[pos] == ' ')) {
    int n = 0;
    if (std::sscanf(text.c_str() + pos + 1, "%2d:%2d%n", &h, &m, &n) != 2 || n != 5) throw bad();
    pos += 1 + n;
    if (pos < text.size() && text[pos] == ':') {
      std::size_t e = pos + 1;
      while (e < text.size() && (std::isdigit(static_cast<unsigned char>(text[e])) || text[e] == '.')) ++e;
      if (!to_double(text.substr(pos + 1, e - pos - 1), s)) throw bad();
      pos = e;
    }
  }
  double offset = 0;
  if (pos < text.size()) {
    const std::string zone = text.substr(pos);
    int oh = 0, om = 0;
    if (zone == "Z" || zone == "z") {
    } else if ((zone[0] == '+' || zone[0] == '-') &&
               (std::sscanf(zone.c_str() + 1, "%2d:%2d", &oh, &om) == 2 ||
                (zone.size() == 5 && std::sscanf(zone.c_str() + 1, "%2d%2d", &oh, &om) == 2) ||
                (zone.size() == 3 && std::sscanf(zone.c_str() + 1, "%2d", &oh) == 1))) {
      offset = (zone[0] == '+' ? 1 : -1) * (oh * 3600.0 + om * 60.0);
    } else {
      throw bad();
    }
  }
  if (M < 1 || M > 12 || D < 1 || D > 31 || h > 23 || m > 59 || s >= 61) throw bad();
  return static_cast<double>(days_from_civil(Y, M, D)) * 86400.0 + h * 3600.0 + m * 60.0 + s - offset;
}

Query parse_query(const std::map<std::string, std::string>& params) {
  Query q;
  const auto get = [&](const char* k) -> const std::string* {
    auto it = params.find(k);
    return it == params.end() ? nullptr : &it->second;
  };
  if (auto* v = get("bbox")) {
    const auto parts = split(*v, ',');
    if (parts.size() != 4)
      throw invalid_argument("bbox", "bbox: expected west,south,east,north in degrees, got '" + *v + "'");
    BBox b{number(parts[0], "bbox"), number(parts[1], "bbox"), number(parts[2], "bbox"),
           number(parts[3], "bbox")};
    if (b.west < -180 || b.west > 180 || b.east < -180 || b.east > 180)
      throw invalid_argument("bbox", "bbox: west and east must lie in [-180, 180]");
    if (b.south < -90 || b.north > 90 || b.south >= b.north)
      throw invalid_argument("bbox", "bbox: need -90 <= south < north <= 90");
    q.bbox = b;
  }
  if (auto* v = get("t0")) q.t0 = parse_time(*v, "t0");
  if (auto* v = get("t1")) q.t1 = parse_time(*v, "t1");
  if (q.t0 && q.t1) {
    if (*q.t1 <= *q.t0) throw invalid_argument("t1", "t1 must be later than t0 (the window is [t0, t1))");
    if (*q.t1 - *q.t0 > limits::kMaxQuerySpanSeconds)
      throw invalid_argument("t1", "t1 - t0 exceeds the longest window of 366 days");
  }
  double unit = kFeetToMetres;
  if (auto* v = get("alt_unit")) {
    if (*v == "m")
      unit = 1.0;
    else if (*v != "ft")
      throw invalid_argument("alt_unit", "alt_unit must be 'ft' or 'm', got '" + *v + "'");
  }
  if (auto* v = get("alt_min")) q.alt_min = number(*v, "alt_min") * unit;
  if (auto* v = get("alt_max")) q.alt_max = number(*v, "alt_max") * unit;
  if (q.alt_min && q.alt_max && *q.alt_min > *q.alt_max)
    throw invalid_argument("alt_max", "alt_max must not be below alt_min");
  if (auto* v = get("icao24"); v && !v->empty()) {
    for (std::string a : split(*v, ',')) {
      a = trim(a);
      std::transform(a.begin(), a.end(), a.begin(), [](unsigned char c) { return std::tolower(c); });
      if (a.size() != 6 || a.find_first_not_of("0123456789abcdef") != std::string::npos)
        throw invalid_argument("icao24", "icao24: '" + a + "' is not a 6-digit hex address");
      q.icao24.push_back(a);
    }
    if (q.icao24.size() > limits::kMaxIcao24PerQuery)
      throw invalid_argument("icao24", "icao24: at most 1000 addresses per query");
    std::sort(q.icao24.begin(), q.icao24.end());
    q.icao24.erase(std::unique(q.icao24.begin(), q.icao24.end()), q.icao24.end());
  }
  if (auto* v = get("callsign"); v && !v->empty()) {
    std::string c = trim(*v);
    if (c.size() > limits::kMaxCallsignPatternLength)
      throw invalid_argument("callsign", "callsign: pattern longer than 16 characters");
    for (char& ch : c) {
      if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '*' && ch != '?')
        throw invalid_argument("callsign", "callsign: only letters, digits, '*' and '?' are allowed");
      ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    }
    q.callsign = c;
  }
  if (auto* v = get("on_ground")) {
    if (*v == "true" || *v == "1")
      q.on_ground = true;
    else if (*v == "false" || *v == "0")
      q.on_ground = false;
    else
      throw invalid_argument("on_ground", "on_ground must be true or false, got '" + *v + "'");
  }
  return q;
}

}  // namespace trailscope
