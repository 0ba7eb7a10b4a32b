#include "formats/animation_chunk.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"
#include "trailscope/core/text.hpp"
#include "trailscope/geo/web_mercator.hpp"

namespace trailscope::server {

namespace {
constexpr std::size_t kHeaderBytes = 64, kFlightBytes = 24;

std::size_t pad8(std::size_t n) {
  return (n + 7) & ~std::size_t{7};
}

// Little-endian stores at a byte offset; every supported host is little-endian, so memcpy is the
// encoding (checked at compile time).
static_assert(std::endian::native == std::endian::little,
              "TSAN is written by memcpy on a little-endian host");
template <typename T>
void put(std::string& buf, std::size_t off, T v) {
  std::memcpy(buf.data() + off, &v, sizeof v);
}

// The flight's icao24 as a 24-bit number, 0xFFFFFFFF when it is not a 6-digit hex address.
std::uint32_t icao24_number(const std::string& s) {
  if (s.size() != 6) return 0xFFFFFFFFu;
  std::uint32_t v = 0;
  for (char c : s) {
    int d;
    if (c >= '0' && c <= '9')
      d = c - '0';
    else if (c >= 'a' && c <= 'f')
      d = c - 'a' + 10;
    else if (c >= 'A' && c <= 'F')
      d = c - 'A' + 10;
    else
      return 0xFFFFFFFFu;
    v = v << 4 | static_cast<std::uint32_t>(d);
  }
  return v;
}
}  // namespace

void check_animation_chunk_start(double t, std::int64_t duration_s) {
  const double d = static_cast<double>(duration_s);
  if (std::fmod(t, d) == 0) return;
  const double before = std::floor(t / d) * d;
  throw invalid_argument("t", "t: chunks start at multiples of duration=" + std::to_string(duration_s) +
                                  "; the nearest starts are " + format_double(before) + " and " +
                                  format_double(before + d));
}

AnimationOrigin default_animation_origin(const TrailSet& set) {
  if (set.num_points() == 0) return {};
  return {(static_cast<double>(set.lon_min()) + set.lon_max()) / 2,
          (static_cast<double>(set.lat_min()) + set.lat_max()) / 2};
}

AnimationOrigin parse_animation_origin(const std::string& text, const std::string& param) {
  const auto bad = [&] {
    return invalid_argument(param, param + ": expected 'lon,lat' in degrees (lon in [-180, 180], |lat| <= " +
                                       "85.0511287798), got '" + text + "'");
  };
  const auto comma = text.find(',');
  if (comma == std::string::npos || text.find(',', comma + 1) != std::string::npos) throw bad();
  AnimationOrigin o;
  try {
    std::size_t used = 0;
    const std::string a = text.substr(0, comma), b = text.substr(comma + 1);
    o.lon = std::stod(a, &used);
    if (used != a.size()) throw bad();
    o.lat = std::stod(b, &used);
    if (used != b.size()) throw bad();
  } catch (const std::logic_error&) {  // stod: no number, or out of range
    throw bad();
  }
  if (!(o.lon >= -180 && o.lon <= 180) || !(std::fabs(o.lat) <= geo::kMaxLatitude)) throw bad();
  return o;
}

std::string encode_animation_chunk(const TrailSet& set, const AnimationChunk& chunk, AnimationOrigin origin) {
  const auto& pts = set.points();
  const auto& flights = set.flights();
  const std::size_t F = chunk.flights.size(), N = chunk.samples;
  if (N > std::numeric_limits<std::uint32_t>::max() || F > std::numeric_limits<std::uint32_t>::max())
    throw Error(Error::Kind::internal, "", "an animation chunk over 2^32 samples cannot be encoded");
  std::size_t strings = 0;
  for (const ChunkFlight& c : chunk.flights) strings += flights[c.flight_id].callsign.size();
  const std::size_t col = pad8(4 * N);
  const std::size_t off_flights = kHeaderBytes, off_cols = off_flights + kFlightBytes * F;
  const std::size_t off_ground = off_cols + 7 * col, off_strings = off_ground + pad8(N);
  std::string buf(off_strings + pad8(strings), '\0');  // zero padding and reserved fields

  const double ox = geo::lon_to_meters_x(origin.lon), oy = geo::lat_to_meters_y(origin.lat);
  std::memcpy(buf.data(), "TSAN", 4);
  put<std::uint16_t>(buf, 4, 1);
  put<std::uint16_t>(buf, 6, 0);
  put<double>(buf, 8, chunk.t_start);
  put<double>(buf, 16, chunk.duration);
  put<double>(buf, 24, ox);
  put<double>(buf, 32, oy);
  put<std::uint32_t>(buf, 40, static_cast<std::uint32_t>(F));
  put<std::uint32_t>(buf, 44, static_cast<std::uint32_t>(N));
  put<std::uint32_t>(buf, 48, static_cast<std::uint32_t>(strings));

  // Column k of the seven float32 columns starts at off_cols + k·col; memcpy stores compile to plain
  // stores without aliasing the string's chars as floats.
  char* const cols = buf.data() + off_cols;
  const auto set_f32 = [&](int k, std::size_t i, float v) { std::memcpy(cols + k * col + 4 * i, &v, 4); };
  char* const ground = buf.data() + off_ground;
  std::size_t s = 0, str = 0;
  for (std::size_t i = 0; i < F; ++i) {
    const ChunkFlight& c = chunk.flights[i];
    const Flight& f = flights[c.flight_id];
    const std::size_t rec = off_flights + kFlightBytes * i;
    put<std::uint32_t>(buf, rec, c.flight_id);
    put<std::uint32_t>(buf, rec + 4, static_cast<std::uint32_t>(s));
    put<std::uint32_t>(buf, rec + 8, c.size());
    put<std::uint32_t>(buf, rec + 12, icao24_number(f.icao24));
    put<std::uint32_t>(buf, rec + 16, static_cast<std::uint32_t>(str));
    put<std::uint32_t>(buf, rec + 20, static_cast<std::uint32_t>(f.callsign.size()));
    std::memcpy(buf.data() + off_strings + str, f.callsign.data(), f.callsign.size());
    str += f.callsign.size();
    for (std::uint32_t p = c.begin; p != c.end; ++p, ++s) {
      // Differences in double, rounded to float once: the rounding is the only error.
      set_f32(0, s, static_cast<float>(pts.t[p] - chunk.t_start));
      set_f32(1, s, static_cast<float>(geo::lon_to_meters_x(pts.lon[p]) - ox));
      set_f32(2, s, static_cast<float>(geo::lat_to_meters_y(pts.lat[p]) - oy));
      set_f32(3, s, pts.alt[p]);
      set_f32(4, s, pts.speed[p]);
      set_f32(5, s, pts.track[p]);
      set_f32(6, s, pts.vrate[p]);
      ground[s] = pts.on_ground[p] ? 1 : 0;
    }
  }
  return buf;
}

nlohmann::json animation_chunk_json(const TrailSet& set, const AnimationChunk& chunk,
                                    AnimationOrigin origin) {
  const auto& pts = set.points();
  const auto& flights = set.flights();
  nlohmann::json list = nlohmann::json::array();
  for (const ChunkFlight& c : chunk.flights) {
    const Flight& f = flights[c.flight_id];
    nlohmann::json samples = nlohmann::json::array();
    for (std::uint32_t p = c.begin; p != c.end; ++p)
      samples.push_back({{"t", pts.t[p]},
                         {"lat", pts.lat[p]},
                         {"lon", pts.lon[p]},
                         {"alt_m", number_or_null(pts.alt[p])},
                         {"speed_ms", number_or_null(pts.speed[p])},
                         {"track_deg", number_or_null(pts.track[p])},
                         {"vrate_ms", number_or_null(pts.vrate[p])},
                         {"on_ground", pts.on_ground[p] != 0}});
    list.push_back({{"id", c.flight_id},
                    {"icao24", f.icao24},
                    {"callsign", f.callsign},
                    {"samples", std::move(samples)}});
  }
  return {{"t", chunk.t_start},
          {"duration", chunk.duration},
          {"origin", {origin.lon, origin.lat}},
          {"count", chunk.flights.size()},
          {"samples", chunk.samples},
          {"flights", std::move(list)}};
}

}  // namespace trailscope::server
