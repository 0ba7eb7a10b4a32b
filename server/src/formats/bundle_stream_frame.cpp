// The TSBS frame of a bundle-stream update (bundle_stream_frame.hpp, proto/bundle_stream.md).
#include "formats/bundle_stream_frame.hpp"

#include <cstring>

#include "trailscope/geo/web_mercator.hpp"

namespace trailscope::server {
namespace {

constexpr double kWorld = static_cast<double>(geo::kWorldUnits);

void put_u32(std::string& out, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out[at + i] = static_cast<char>((v >> (8 * i)) & 0xff);
}
void put_f32(std::string& out, std::size_t at, float v) {
  std::uint32_t u;
  std::memcpy(&u, &v, 4);
  put_u32(out, at, u);
}

}  // namespace

std::string encode_stream_frame(const bundling::StreamUpdate& u, const bundling::Frame& frame,
                                double window_s) {
  const std::size_t n = u.id.size(), m = u.lines.points();
  std::string out(44 + 12 * n + 8 * m, '\0');
  std::memcpy(out.data(), "TSBS", 4);
  put_u32(out, 4, 1);
  put_u32(out, 8, static_cast<std::uint32_t>(n));
  put_u32(out, 12, static_cast<std::uint32_t>(m));
  std::uint64_t tb;
  std::memcpy(&tb, &u.t, 8);
  for (int i = 0; i < 8; ++i) out[16 + i] = static_cast<char>((tb >> (8 * i)) & 0xff);
  put_u32(out, 24, static_cast<std::uint32_t>(u.sequence));
  put_f32(out, 28, static_cast<float>(window_s));
  put_f32(out, 32, static_cast<float>(u.drift_px));
  put_u32(out, 36, 0);
  std::size_t at = 40;
  for (std::size_t e = 0; e < n; ++e, at += 4) put_u32(out, at, static_cast<std::uint32_t>(u.id[e]));
  for (std::size_t e = 0; e < n; ++e, at += 4) put_f32(out, at, u.opacity[e]);
  for (std::size_t e = 0; e <= n; ++e, at += 4) put_u32(out, at, u.lines.offsets[e]);
  for (std::size_t i = 0; i < m; ++i, at += 8) {
    const double x = frame.from_px_x(u.lines.x[i]) / kWorld, y = frame.from_px_y(u.lines.y[i]) / kWorld;
    put_f32(out, at, static_cast<float>(geo::unit_x_to_lon(x)));
    put_f32(out, at + 4, static_cast<float>(geo::unit_y_to_lat(y)));
  }
  return out;
}

}  // namespace trailscope::server
