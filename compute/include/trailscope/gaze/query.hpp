#pragma once
// Selecting from a gaze dataset (gaze.hpp) and the answers built on the selection: detected events with
// their positions, and scanpaths (each recording's fixations in time order). One filter for every view
// of a stored gaze dataset (the events, scanpaths, tiles and AOI routes, and the CLI), so that a
// participant, stimulus, recording or time window means the same thing everywhere.
//
// Windows are relative: `t0_ms`/`t1_ms` count from each recording's first sample, so one window picks the
// same stretch of every trial whatever the tracker's clock read when it started. A sample is in the
// window when t - t_first lies in [t0_ms, t1_ms); an event is in it when its first sample is.
// Events are always detected on the whole recording (never on the window alone), so an event and its
// bounds do not depend on the window that shows it.
#include <array>
#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "trailscope/gaze/events.hpp"
#include "trailscope/gaze/gaze.hpp"

namespace trailscope::gaze {

struct GazeFilter {
  std::optional<std::string> participant;  ///< only recordings of this participant (exact match)
  std::optional<std::string> stimulus;     ///< only recordings of this stimulus (exact; "" is a value)
  std::optional<std::size_t> recording;    ///< only this recording (index in the dataset, from 0)
  double t0_ms = 0;                        ///< window start, ms after each recording's first sample, >= 0
  double t1_ms = std::numeric_limits<double>::infinity();  ///< window end (exclusive), > t0_ms
};

/// The indices of the recordings the filter keeps, ascending. Throws Error(invalid_argument, param, ...)
/// when a value names nothing in `ds` (so a typo is an error, not an empty answer):
///  - "participant": "participant 'P' is not in this gaze dataset (its participants: a, b, ...)";
///  - "stimulus": the same with the stimuli;
///  - "recording": "recording must lie in 0..N-1, got K";
///  - "t1_ms": "t1_ms must be later than t0_ms ..." when the window is empty; "t0_ms" when t0_ms < 0 or a
///    bound is NaN.
/// A participant and a stimulus that exist but never together select nothing (an empty list).
std::vector<std::size_t> select_recordings(const GazeDataset& ds, const GazeFilter& f);

/// The samples of `r` in the filter's window: [first, last) indices, assuming times do not decrease
/// (the detectors' requirement; a file whose clock goes back is rejected by them). Empty for an empty
/// recording.
std::pair<std::size_t, std::size_t> window_samples(const Recording& r, const GazeFilter& f);

/// "fixation" | "saccade" | "pso" | "pursuit" | "blink" | "undefined" (gaze.hpp to_string); throws
/// Error(invalid_argument, param, ...) listing them otherwise.
EventType parse_event_type(std::string_view text, const std::string& param = "type");

/// One detected event of a recording, with positions in the recording's units (px or deg):
///  - fixation: (x, y) the mean of its valid samples; x_end, y_end NaN;
///  - saccade and pso: (x, y) its first valid sample, (x_end, y_end) its last;
///  - blink, pursuit, undefined: all four NaN.
/// Times are on the tracker's clock (not relative); duration_ms = t_end_ms - t_start_ms (last sample
/// minus first, as the detectors report events).
struct EventRow {
  std::size_t recording = 0;
  EventType type = EventType::none;
  double t_start_ms = 0, t_end_ms = 0;
  double x = 0, y = 0, x_end = 0, y_end = 0;
};

struct EventList {
  std::vector<EventRow> events;  ///< by recording, then time
  /// Events returned per EventType code (index = the code).
  std::array<std::size_t, 7> counts{};
};

/// Detects events (detect_events with `p`) in every selected recording and returns those in the window
/// whose type is in `types` (every type but none when empty). Throws select_recordings' and
/// detect_events' errors (Error(invalid_argument, "geometry") for px recordings without a physical
/// screen; parameter errors), and Error(payload_too_large, "events", ...) naming `max_events` when more
/// events than that would be returned (counted before any row is built). Linear in the samples of the
/// selected recordings.
EventList list_events(const GazeDataset& ds, const GazeFilter& f, const EventParams& p,
                      const std::vector<EventType>& types, std::size_t max_events);

/// One fixation of a scanpath (positions in the recording's units, times on the tracker's clock).
struct ScanpathFixation {
  double x = 0, y = 0, t_start_ms = 0, duration_ms = 0;
};
struct Scanpath {
  std::size_t recording = 0;
  std::string participant, stimulus;
  std::vector<ScanpathFixation> fixations;  ///< in time order
};

/// The fixations (list_events' fixation rows) of every selected recording in the window, one scanpath per
/// selected recording (an empty one too), by recording index. Throws as list_events, `max_fixations`
/// counting the fixations of all scanpaths together.
std::vector<Scanpath> scanpaths(const GazeDataset& ds, const GazeFilter& f, const EventParams& p,
                                std::size_t max_fixations);

}  // namespace trailscope::gaze
