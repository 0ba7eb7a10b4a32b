// Format names and content-based detection.
#include "trailscope/ingest/format.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>

#include <nlohmann/json.hpp>

#include "ingest/detail.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::ingest {
namespace {

constexpr std::array<std::pair<Format, const char*>, 4> kNames{{
    {Format::opensky_csv, "opensky_csv"},
    {Format::traffic_json, "traffic_json"},
    {Format::so6, "so6"},
    {Format::readsb_trace, "readsb_trace"},
}};

constexpr const char* kSupported =
    "supported formats: opensky_csv (OpenSky state_vectors_data4 CSV with a time,icao24,lat,lon,... header), "
    "traffic_json (JSON array or JSON Lines of records with timestamp, icao24, latitude, longitude), "
    "so6 (Eurocontrol SO6 m3 segment lines), readsb_trace (readsb trace_full JSON with icao, timestamp, "
    "trace); each plain or gzip-compressed";

[[noreturn]] void unsupported(const std::string& seen) {
  throw Error(Error::Kind::unsupported_format, "format",
              "not a supported trail file: " + seen + "; " + kSupported);
}

bool starts_with(std::string_view s, std::string_view prefix) {
  return s.size() >= prefix.size() && s.substr(0, prefix.size()) == prefix;
}

// Names well-known binary signatures, so the message says "a PNG image" rather than "garbage".
const char* binary_kind(std::string_view h) {
  using namespace std::string_view_literals;
  if (starts_with(h, "\x89PNG\r\n\x1a\n"sv)) return "a PNG image";
  if (starts_with(h, "\xff\xd8\xff"sv)) return "a JPEG image";
  if (starts_with(h, "GIF87a"sv) || starts_with(h, "GIF89a"sv)) return "a GIF image";
  if (starts_with(h, "PK\x03\x04"sv)) return "a ZIP archive";
  if (starts_with(h, "7z\xbc\xaf\x27\x1c"sv)) return "a 7-Zip archive";
  if (starts_with(h,
                  "\xfd"
                  "7zXZ\x00"sv))
    return "xz-compressed data";
  if (starts_with(h, "\x28\xb5\x2f\xfd"sv)) return "zstd-compressed data";
  if (h.size() >= 4 && starts_with(h, "BZh"sv) && h[3] >= '1' && h[3] <= '9') return "bzip2-compressed data";
  if (starts_with(h, "\x1f\x8b"sv)) return "gzip data inside gzip (compressed twice)";
  if (starts_with(h, "%PDF"sv)) return "a PDF document";
  if (starts_with(h, "PAR1"sv)) return "a Parquet file (convert it to CSV first)";
  if (starts_with(h, "ARROW1"sv)) return "an Arrow IPC file (convert it to CSV first)";
  if (starts_with(h, "SQLite format 3\0"sv)) return "an SQLite database";
  return nullptr;
}

// Text formats never contain NUL, and few control bytes other than tab/CR/LF/FF.
bool looks_binary(std::string_view h) {
  const std::size_t n = std::min<std::size_t>(h.size(), 4096);
  std::size_t control = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto c = static_cast<unsigned char>(h[i]);
    if (c == 0) return true;
    if (c < 32 && c != '\t' && c != '\n' && c != '\r' && c != '\f') ++control;
  }
  return control * 20 > n;  // more than 5 %
}

std::string hex_bytes(std::string_view h, std::size_t n = 8) {
  std::string out;
  char buf[4];
  for (std::size_t i = 0; i < std::min(n, h.size()); ++i) {
    std::snprintf(buf, sizeof buf, "%s%02x", i ? " " : "", static_cast<unsigned char>(h[i]));
    out += buf;
  }
  return out;
}

// Collects the keys of the first record: the top-level object, or the first element of a top-level
// array. Stops at the end of that record, or at the end of the (possibly cut) head.
class KeySniffer : public nlohmann::json_sax<nlohmann::json> {
 public:
  bool top_is_array = false, top_seen = false, first_is_object = false;
  std::vector<std::string> keys;

  bool null() override { return element(); }
  bool boolean(bool) override { return element(); }
  bool number_integer(number_integer_t) override { return element(); }
  bool number_unsigned(number_unsigned_t) override { return element(); }
  bool number_float(number_float_t, const string_t&) override { return element(); }
  bool string(string_t&) override { return element(); }
  bool binary(binary_t&) override { return element(); }
  bool start_object(std::size_t) override {
    if (depth_ == 0) {
      top_seen = true;
      record_depth_ = 1;
      first_is_object = true;
    } else if (depth_ == 1 && top_is_array && record_depth_ == 0) {
      record_depth_ = 2;
      first_is_object = true;
    }
    ++depth_;
    return true;
  }
  bool key(string_t& k) override {
    if (depth_ == record_depth_) keys.push_back(k);
    return true;
  }
  bool end_object() override {
    if (depth_-- == record_depth_) return false;  // first record complete: stop
    return true;
  }
  bool start_array(std::size_t) override {
    if (depth_ == 0)
      top_seen = true, top_is_array = true;
    else if (depth_ == 1 && top_is_array && record_depth_ == 0)
      return false;  // first element not an object
    ++depth_;
    return true;
  }
  bool end_array() override {
    --depth_;
    return depth_ != 0;
  }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override {
    return false;
  }

 private:
  // A scalar as the first element of a top-level array means "not records".
  bool element() { return !(depth_ == 1 && top_is_array && record_depth_ == 0); }
  int depth_ = 0, record_depth_ = 0;
};

bool has_all(const std::vector<std::string>& keys, std::initializer_list<const char*> wanted) {
  return std::all_of(wanted.begin(), wanted.end(),
                     [&](const char* w) { return std::find(keys.begin(), keys.end(), w) != keys.end(); });
}

std::string join(const std::vector<std::string>& v, std::size_t max = 12) {
  std::string out;
  for (std::size_t i = 0; i < v.size() && i < max; ++i) out += (i ? ", " : "") + v[i];
  if (v.size() > max) out += ", ...";
  return out;
}

Format detect_json(std::string_view text) {
  KeySniffer sniffer;
  nlohmann::json::sax_parse(text.begin(), text.end(), &sniffer, nlohmann::json::input_format_t::json, false);
  if (!sniffer.top_is_array && has_all(sniffer.keys, {"icao", "trace"})) return Format::readsb_trace;
  if (has_all(sniffer.keys, {"timestamp", "icao24", "latitude", "longitude"})) return Format::traffic_json;
  if (!sniffer.first_is_object)
    unsupported(sniffer.top_is_array ? "a JSON array that is empty or whose first element is not an object"
                                     : "JSON that is neither an array of records nor an object");
  unsupported(
      "JSON whose first record has the keys [" + join(sniffer.keys) +
      "] (traffic_json needs timestamp, icao24, latitude, longitude; readsb_trace needs icao, trace)");
}

}  // namespace

Format parse_format(std::string_view text, const std::string& param) {
  for (const auto& [f, name] : kNames)
    if (text == name) return f;
  throw invalid_argument(param, "unknown format " + detail::quote(text) +
                                    "; expected one of opensky_csv, traffic_json, so6, readsb_trace");
}

const char* to_string(Format f) noexcept {
  for (const auto& [g, name] : kNames)
    if (f == g) return name;
  return "unknown";
}

Format detect_format(std::string_view head) {
  using namespace std::string_view_literals;
  if (starts_with(head, "\xef\xbb\xbf"sv)) head.remove_prefix(3);
  std::size_t first = head.find_first_not_of(" \t\r\n\f");
  if (first == std::string_view::npos) unsupported(head.empty() ? "the file is empty" : "the file is blank");
  if (const char* kind = binary_kind(head)) unsupported(std::string(kind));
  if (looks_binary(head)) unsupported("binary data (first bytes " + hex_bytes(head) + ")");
  const std::string_view text = head.substr(first);
  if (text.front() == '[' || text.front() == '{') return detect_json(text);

  const std::string_view line = detail::first_line(text);
  if (line.find(',') != std::string_view::npos) {
    const auto names = detail::csv_header_names(line);
    std::vector<std::string> missing;
    for (const char* need : {"time", "icao24", "lat", "lon"})
      if (std::find(names.begin(), names.end(), need) == names.end()) missing.emplace_back(need);
    if (missing.empty()) return Format::opensky_csv;
    unsupported("a CSV header " + detail::quote(line, 80) + " without the OpenSky column(s) " +
                join(missing) + " (opensky_csv needs time, icao24, lat, lon)");
  }
  detail::So6Segment seg;
  const char* why = detail::parse_so6_line(line, seg);
  if (!why) return Format::so6;
  unsupported("text whose first line " + detail::quote(line, 80) +
              " is neither a CSV header nor an SO6 segment (" + why + ")");
}

}  // namespace trailscope::ingest
