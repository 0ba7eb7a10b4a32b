#pragma once
// Float images <-> the 16-bit counts stored in PNGs, and the pack trailer. Internal to compute/src/tof.
#include <cstdint>
#include <string_view>
#include <vector>

namespace trailscope::tof::detail {

/// Depth mm -> counts: whole mm (round half away from zero), 0 for NaN, at least 1 for a return (so a
/// return under 0.5 mm does not turn into a hole). Throws Error(invalid_argument, "frame") naming `frame`
/// and the pixel for depth > 65535 mm.
std::vector<std::uint16_t> depth_to_counts(const std::vector<float>& depth_mm, std::size_t frame);
/// Counts -> depth mm: 0 -> NaN, else count * unit_mm.
std::vector<float> counts_to_depth(const std::vector<std::uint16_t>& counts, double unit_mm);
/// Amplitude -> counts: round(a / scale), clamped to 65535 (a saturated sensor).
std::vector<std::uint16_t> amplitude_to_counts(const std::vector<float>& amplitude, double scale);
std::vector<float> counts_to_amplitude(const std::vector<std::uint16_t>& counts, double scale);

/// Pack trailer: manifest offset (u64 LE), manifest length (u64 LE), magic.
inline constexpr std::string_view kPackMagic = "TSDVPK01";
inline constexpr std::size_t kPackTrailerBytes = 24;

}  // namespace trailscope::tof::detail
