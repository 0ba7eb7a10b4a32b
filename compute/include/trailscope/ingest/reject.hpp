#pragma once
// Row validation shared by every reader: which samples are accepted into a TrailSet, and the record of
// those that are not. TrailSetBuilder::add() trusts its input (it only asserts finite time and position),
// so every reader runs a sample through normalise_sample() and check_sample() first.
#include <cstddef>
#include <string>
#include <string_view>

#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::ingest {

/// One rejected input row. `line` is the 1-based line of a text file (CSV, SO6, JSON Lines) or the
/// 1-based record index of a JSON array / readsb trace; `reason` is a short English sentence.
struct Reject {
  std::size_t line = 0;
  std::string reason;
};

// Sanity ranges. They are deliberately wide: they reject values that cannot be physical (a corrupt
// field, a unit mix-up such as milliseconds in a seconds column), not unusual flights.
/// Accepted times, Unix seconds: 1970-01-01 up to 2100-01-01.
inline constexpr double kMinTime = 0.0;
inline constexpr double kMaxTime = 4102444800.0;
/// Accepted altitudes, metres: from below the Dead Sea (barometric altitudes in high pressure read low)
/// up to stratospheric balloons, which do transmit ADS-B.
inline constexpr float kMinAltitude = -1500.0f;
inline constexpr float kMaxAltitude = 50000.0f;
/// Largest accepted ground speed, m/s (about Mach 4.4).
inline constexpr float kMaxSpeed = 1500.0f;
/// Largest accepted |vertical rate|, m/s (ADS-B encodes at most 32,608 ft/min = 166 m/s).
inline constexpr float kMaxVerticalRate = 200.0f;

/// True for exactly six hexadecimal digits (either case): a 24-bit ICAO aircraft address.
bool is_icao24(std::string_view text) noexcept;

/// Brings representable-but-unusual values into the canonical ranges of PointColumns: longitude 180 →
/// -180, track modulo 360 into [0, 360). Values outside the sanity ranges are left for check_sample().
void normalise_sample(Sample& s) noexcept;

/// nullptr when `s` is acceptable; otherwise a static English reason ("latitude out of range [-90, 90]",
/// "time out of range (expected Unix seconds 1970..2100)", ...). NaN optional fields (alt, speed, track,
/// vrate) are fine; NaN time or position is not.
const char* check_sample(const Sample& s) noexcept;

}  // namespace trailscope::ingest
