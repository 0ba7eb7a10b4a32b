// Validation (reject.hpp) and the small parsing helpers every reader shares.
#include <cctype>
#include <cmath>

#include "ingest/detail.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/ingest/reject.hpp"

namespace trailscope::ingest {

bool is_icao24(std::string_view text) noexcept {
  if (text.size() != 6) return false;
  for (char c : text)
    if (!std::isxdigit(static_cast<unsigned char>(c))) return false;
  return true;
}

void normalise_sample(Sample& s) noexcept {
  if (s.lon == 180.0f) s.lon = -180.0f;
  if (std::isfinite(s.track) && (s.track < 0.0f || s.track >= 360.0f)) {
    s.track = std::fmod(s.track, 360.0f);
    if (s.track < 0.0f) s.track += 360.0f;
    if (s.track >= 360.0f) s.track = 0.0f;  // fmod of a tiny negative can round up to 360
  }
}

const char* check_sample(const Sample& s) noexcept {
  if (!std::isfinite(s.t)) return "time missing";
  if (s.t < kMinTime || s.t >= kMaxTime) return "time out of range (expected Unix seconds, 1970..2100)";
  if (!std::isfinite(s.lat) || !std::isfinite(s.lon)) return "missing position";
  if (s.lat < -90.0f || s.lat > 90.0f) return "latitude out of range [-90, 90]";
  if (s.lon < -180.0f || s.lon > 180.0f) return "longitude out of range [-180, 180]";
  // Comparisons with NaN are false, so unknown optional values pass.
  if (s.alt < kMinAltitude || s.alt > kMaxAltitude) return "altitude out of range [-1500, 50000] m";
  if (s.speed < 0.0f || s.speed > kMaxSpeed) return "ground speed out of range [0, 1500] m/s";
  if (std::isinf(s.track)) return "track is not finite";
  if (s.vrate < -kMaxVerticalRate || s.vrate > kMaxVerticalRate)
    return "vertical rate out of range [-200, 200] m/s";
  return nullptr;
}

namespace detail {

std::string quote(std::string_view s, std::size_t max) {
  std::string out = "'";
  for (std::size_t i = 0; i < s.size() && i < max; ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    // ASCII only: a quoted field of a damaged file must not put invalid UTF-8 into messages and JSON.
    out += (c < 32 || c >= 127) ? '?' : static_cast<char>(c);
  }
  if (s.size() > max) out += "...";
  out += "'";
  return out;
}

std::string_view first_line(std::string_view text) noexcept {
  std::string_view line = text.substr(0, text.find('\n'));
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  return line;
}

void split_csv(std::string_view line, std::vector<std::string_view>& fields) {
  fields.clear();
  std::size_t i = 0;
  const std::size_t n = line.size();
  for (;;) {
    if (i < n && line[i] == '"') {
      std::size_t j = i + 1;
      for (;;) {
        j = line.find('"', j);
        if (j == std::string_view::npos) {  // unterminated: take the rest
          fields.push_back(line.substr(i + 1));
          return;
        }
        if (j + 1 < n && line[j + 1] == '"') {
          j += 2;
          continue;
        }
        break;
      }
      fields.push_back(line.substr(i + 1, j - i - 1));
      const std::size_t comma = line.find(',', j + 1);
      if (comma == std::string_view::npos) return;
      i = comma + 1;
    } else {
      const std::size_t comma = line.find(',', i);
      if (comma == std::string_view::npos) {
        fields.push_back(line.substr(i));
        return;
      }
      fields.push_back(line.substr(i, comma - i));
      i = comma + 1;
    }
  }
}

std::vector<std::string> csv_header_names(std::string_view line) {
  using namespace std::string_view_literals;
  if (line.substr(0, 3) == "\xef\xbb\xbf"sv) line.remove_prefix(3);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  std::vector<std::string_view> fields;
  split_csv(line, fields);
  std::vector<std::string> names;
  names.reserve(fields.size());
  for (std::string_view f : fields) {
    f = trim(f);
    if (f.size() >= 2 && f.front() == '"' && f.back() == '"') f = f.substr(1, f.size() - 2);
    std::string name(f);
    for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    names.push_back(std::move(name));
  }
  return names;
}

namespace {
// Reads exactly `n` digits at s[i...] into `v`; advances i.
bool digits(std::string_view s, std::size_t& i, int n, int& v) noexcept {
  if (i + n > s.size()) return false;
  v = 0;
  for (int k = 0; k < n; ++k) {
    const char c = s[i + k];
    if (c < '0' || c > '9') return false;
    v = v * 10 + (c - '0');
  }
  i += n;
  return true;
}
}  // namespace

bool parse_iso8601(std::string_view s, double& t) noexcept {
  s = trim(s);
  std::size_t i = 0;
  int y, mo, d, h = 0, mi = 0, sec = 0;
  double frac = 0;
  if (!digits(s, i, 4, y) || i >= s.size() || s[i++] != '-' || !digits(s, i, 2, mo) || i >= s.size() ||
      s[i++] != '-' || !digits(s, i, 2, d))
    return false;
  if (mo < 1 || mo > 12 || d < 1 || d > 31) return false;
  if (i < s.size() && (s[i] == 'T' || s[i] == 't' || s[i] == ' ')) {
    ++i;
    if (!digits(s, i, 2, h) || i >= s.size() || s[i++] != ':' || !digits(s, i, 2, mi)) return false;
    if (i < s.size() && s[i] == ':') {
      ++i;
      if (!digits(s, i, 2, sec)) return false;
      if (i < s.size() && (s[i] == '.' || s[i] == ',')) {
        double scale = 0.1;
        ++i;
        const std::size_t start = i;
        while (i < s.size() && s[i] >= '0' && s[i] <= '9') frac += (s[i++] - '0') * scale, scale *= 0.1;
        if (i == start) return false;
      }
    }
    if (h > 24 || mi > 59 || sec > 60) return false;
  }
  int offset = 0;  // seconds east of UTC
  if (i < s.size()) {
    if (s[i] == 'Z' || s[i] == 'z') {
      ++i;
    } else if (s[i] == '+' || s[i] == '-') {
      const int sign = s[i++] == '-' ? -1 : 1;
      int oh = 0, om = 0;
      if (!digits(s, i, 2, oh)) return false;
      if (i < s.size() && s[i] == ':') ++i;
      if (i < s.size() && !digits(s, i, 2, om)) return false;
      offset = sign * (oh * 3600 + om * 60);
    }
  }
  if (i != s.size()) return false;
  t = static_cast<double>(days_from_civil(y, static_cast<unsigned>(mo), static_cast<unsigned>(d)) * 86400 +
                          h * 3600 + mi * 60 + sec - offset) +
      frac;
  return true;
}

void ReadContext::checkpoint() {
  if (opts.cancel) opts.cancel->throw_if_cancelled();
  if (opts.progress) opts.progress(src.fraction(), "parse");
}

}  // namespace detail
}  // namespace trailscope::ingest
