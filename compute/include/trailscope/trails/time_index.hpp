#pragma once
// A time index of a TrailSet, built once when the set is constructed (at ingest and at load), so that a
// time-window read touches only the flights and points of its window, and a window summary over whole
// hours adds up counts made at ingest instead of scanning their points:
//  - the flights' start order (TrailSetBuilder gives flights in start order) with a running maximum of
//    their end times: the flights that may meet [t0, t1) are one index range, found by two binary
//    searches; within a flight the points of the window are one range too (points are time-sorted);
//  - per time bucket (bucket_seconds(): 10 minutes, or a multiple of 10 minutes when the data spans more
//    than kMaxBuckets of them (a week) or has fewer than kMinPointsPerBucket points per bucket) the additive
//    part of a summary of all its points: count, first and last time, altitude histograms in both units
//    (ft and m) over the bins summarize() uses for this set, the speed histogram of 0.25 m/s bins, and the
//    known-speed count, sum, min and max; plus point counts per fine cell (fine_seconds(), a tenth of a
//    bucket), from which any time histogram whose bins are whole multiples of a fine cell follows exactly;
//  - every implausible value check_quality() can report (trails/quality.hpp) with the time of its sample
//    and, for a jump, of the sample before it: the quality of a time window is the events inside it.
// The fast summary (summary.cpp) adds the whole buckets inside a window and scans only the partial
// buckets at its two ends; its answer equals the scan's in every field (the speed mean up to the order of
// a floating-point sum, which the scan's own parallel reduction does not fix either).
// Memory: 16 bytes per flight (start time, running maximum) + 4 per flight (callsign id) + per bucket
// ~10 KiB (the speed histogram) + 4 bytes per fine cell + 32 bytes per quality event: ~0.5 bytes per point
// for a week of dense traffic.
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace trailscope {

struct PointColumns;
struct Flight;

class TimeIndex {
 public:
  /// Most time buckets; longer spans get wider ones (a year: 9-hour buckets of 54-minute cells).
  static constexpr std::size_t kMaxBuckets = 1024;
  /// At most one bucket per this many points (a small set gets wide buckets, so its index costs in
  /// proportion to its points, not to its time span; summaries of its narrow windows scan).
  static constexpr std::size_t kMinPointsPerBucket = 64;
  /// The index keeps quality events only while they are at most this fraction of the points (real data
  /// has a handful per flight at worst); beyond it summaries take the plain scan (`quality_indexed()`).
  static constexpr double kMaxEventFraction = 0.25;

  /// Per-bucket additive summary of all its points (see summarize(): the same bins and rules).
  struct Bucket {
    std::uint64_t points = 0;
    double t_first = 0, t_last = 0;  ///< first and last point time in the bucket (when points > 0)
    std::uint64_t speed_n = 0;
    double speed_sum = 0, speed_min = 0, speed_max = 0;
    std::vector<std::uint64_t> alt_ft, alt_m;  ///< altitude histograms (SummaryLayout bins for ft and m)
    std::vector<std::uint32_t> speed;          ///< SummaryLayout::kSpeedBins bins of 0.25 m/s
  };
  /// One implausible value (quality.hpp): kind 0 speed, 1 altitude, 2 jump.
  struct Event {
    double t = 0;       ///< time of the sample (of a jump: the sample after it)
    double t_prev = 0;  ///< jumps: time of the sample before it (both must lie in the window)
    double value = 0;   ///< m/s or metres, as check_quality() reports it
    std::uint32_t flight = 0;
    std::uint8_t kind = 0;
  };

  TimeIndex() = default;
  /// Builds the index in parallel. An index is `valid()` only when the flights are in start order
  /// (t_min non-decreasing), every time is finite and every flight's point range lies within `points` (a
  /// set of flights without their points, as the ClickHouse store's outline of a dataset, is not indexed);
  /// otherwise reads fall back to plain scans.
  TimeIndex(const PointColumns& points, const std::vector<Flight>& flights);

  bool valid() const { return valid_; }
  /// The flights that may have a point in [t0, t1) (±infinity for an open side): index range [first,
  /// last); flights inside it may still miss the window (Query::may_match decides). Needs valid().
  std::pair<std::size_t, std::size_t> flight_range(double t0, double t1) const;
  /// Highest known altitude of the set (metres, 0 when none): what summarize() sizes its histogram by.
  double top_alt_m() const { return top_alt_m_; }
  /// Some flight crosses the antimeridian (Flight::crosses_antimeridian).
  bool any_crosses_antimeridian() const { return crosses_; }

  double origin() const { return origin_; }  ///< start of bucket 0 and of fine cell 0 (Unix s)
  double bucket_seconds() const { return bucket_s_; }
  double fine_seconds() const { return fine_s_; }
  const std::vector<Bucket>& buckets() const { return buckets_; }
  const std::vector<std::uint32_t>& fine_counts() const { return fine_; }

  bool quality_indexed() const { return quality_indexed_; }
  /// Quality events in time order (of Event::t).
  const std::vector<Event>& events() const { return events_; }

  /// Dense ids of the flights' callsigns (equal callsigns, equal ids) and the names by id.
  const std::vector<std::uint32_t>& callsign_ids() const { return callsign_ids_; }
  const std::vector<std::string>& callsign_names() const { return callsign_names_; }

  /// Bytes the index holds (for memory accounting).
  std::size_t bytes() const;

 private:
  bool valid_ = false, quality_indexed_ = false, crosses_ = false;
  std::vector<double> t_min_, run_max_;  ///< per flight in order: start time, max end time so far
  double top_alt_m_ = 0;
  double origin_ = 0, bucket_s_ = 3600, fine_s_ = 60;
  std::vector<Bucket> buckets_;
  std::vector<std::uint32_t> fine_;
  std::vector<Event> events_;
  std::vector<std::uint32_t> callsign_ids_;
  std::vector<std::string> callsign_names_;
};

}  // namespace trailscope
