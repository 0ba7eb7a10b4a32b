#include "pixels.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "trailscope/core/error.hpp"

namespace trailscope::tof::detail {

std::vector<std::uint16_t> depth_to_counts(const std::vector<float>& depth_mm, std::size_t frame) {
  std::vector<std::uint16_t> out(depth_mm.size());
  for (std::size_t i = 0; i < depth_mm.size(); ++i) {
    const float z = depth_mm[i];
    if (std::isnan(z)) {
      out[i] = 0;
      continue;
    }
    const double r = std::round(static_cast<double>(z));
    if (r > 65535.0)
      throw invalid_argument("frame", "frame " + std::to_string(frame) + ": depth at pixel " +
                                          std::to_string(i) + " is " + std::to_string(z) +
                                          " mm, beyond the 65535 mm a 16-bit PNG holds");
    out[i] = static_cast<std::uint16_t>(r < 1.0 ? 1.0 : r);
  }
  return out;
}

std::vector<float> counts_to_depth(const std::vector<std::uint16_t>& counts, double unit_mm) {
  std::vector<float> out(counts.size());
  for (std::size_t i = 0; i < counts.size(); ++i)
    out[i] =
        counts[i] == 0 ? std::numeric_limits<float>::quiet_NaN() : static_cast<float>(counts[i] * unit_mm);
  return out;
}

std::vector<std::uint16_t> amplitude_to_counts(const std::vector<float>& amplitude, double scale) {
  std::vector<std::uint16_t> out(amplitude.size());
  for (std::size_t i = 0; i < amplitude.size(); ++i) {
    const double c = std::round(amplitude[i] / scale);
    out[i] = static_cast<std::uint16_t>(c > 65535.0 ? 65535.0 : (c < 0 ? 0.0 : c));
  }
  return out;
}

std::vector<float> counts_to_amplitude(const std::vector<std::uint16_t>& counts, double scale) {
  std::vector<float> out(counts.size());
  for (std::size_t i = 0; i < counts.size(); ++i) out[i] = static_cast<float>(counts[i] * scale);
  return out;
}

}  // namespace trailscope::tof::detail
