#pragma once
// Collects raw samples from any reader and turns them into flights: groups by (icao24, callsign), sorts
// by time, keeps the first of several samples with the same time (later ones count as duplicates), splits at
// gaps longer than limits::kFlightGapSeconds, and computes the per-flight extents. Out-of-order input is
// fine; the builder sorts.
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "trailscope/trails/trail_set.hpp"

namespace trailscope {

/// One raw sample in SI units. Unknown values are NaN (on_ground defaults to airborne).
struct Sample {
  static constexpr float kUnknown = std::numeric_limits<float>::quiet_NaN();
  double t = 0;            ///< Unix seconds
  float lat = 0, lon = 0;  ///< degrees
  float alt = kUnknown;    ///< barometric altitude, metres
  float speed = kUnknown;  ///< ground speed, m/s
  float track = kUnknown;  ///< degrees from true north
  float vrate = kUnknown;  ///< m/s, positive up
  bool on_ground = false;
};

class TrailSetBuilder {
 public:
  /// Adds a sample of the aircraft (icao24, callsign). `icao24` is lower-cased and `callsign` trimmed
  /// and upper-cased here. The caller validates ranges (see ingest/reject.hpp); the builder only
  /// asserts finite time and position.
  void add(std::string_view icao24, std::string_view callsign, const Sample& s);

  /// Number of samples added so far (before deduplication).
  std::size_t size() const { return samples_; }

  struct Stats {
    std::size_t duplicates =
        0;  ///< samples dropped because an identical-time sample of the same aircraft came first
    std::size_t splits = 0;  ///< extra flights created by gaps > kFlightGapSeconds
    /// Extra flights created by teleports and by gaps between two legs (see build()), each with the sample
    /// that starts the new flight: its aircraft, time and, for a teleport, the speed the jump implies
    /// (m/s), for two legs the gap (s).
    std::size_t jump_splits = 0, leg_splits = 0;
    struct Jump {
      std::string icao24, callsign;
      double t = 0, speed_ms = 0;  ///< speed_ms: m/s for jumps, the gap in seconds for legs
    };
    std::vector<Jump> jumps, legs;
  };

  /// Builds the TrailSet; flights are ordered by start time (then icao24, callsign), so that flights
  /// near in time are near in memory. Leaves the builder empty. `gap_seconds` overrides the split gap;
  /// <= 0 means limits::kFlightGapSeconds, +infinity never splits (SO6, whose flights carry their own ids).
  /// `split_jumps` also splits where a flight is two legs (a gap over kLegGapSeconds) or teleports (a
  /// confirmed step beyond kJumpSplitSpeedMs and kJumpSplitMinDistanceM; the rule in trails/quality.hpp),
  /// so that a position no aircraft could have reached starts a new flight instead of drawing a straight
  /// line across the map. A one-point spike is never split off.
  TrailSet build(Stats* stats = nullptr, double gap_seconds = -1.0, bool split_jumps = false);

 private:
  struct Key {
    std::string icao24, callsign;
  };
  struct KeyView {
    std::string_view icao24, callsign;
  };
  // Transparent hash and equality: add() looks a sample's aircraft up by views into reused buffers,
  // so the common case (an aircraft already seen) allocates nothing.
  struct KeyHash {
    using is_transparent = void;
    std::size_t operator()(const KeyView& k) const noexcept;
    std::size_t operator()(const Key& k) const noexcept { return (*this)(KeyView{k.icao24, k.callsign}); }
  };
  struct KeyEq {
    using is_transparent = void;
    static KeyView view(const Key& k) { return {k.icao24, k.callsign}; }
    static KeyView view(const KeyView& k) { return k; }
    template <typename A, typename B>
    bool operator()(const A& a, const B& b) const noexcept {
      return view(a).icao24 == view(b).icao24 && view(a).callsign == view(b).callsign;
    }
  };
  std::unordered_map<Key, std::vector<Sample>, KeyHash, KeyEq> groups_;
  std::string icao_buf_, callsign_buf_;
  std::size_t samples_ = 0;
};

}  // namespace trailscope
