#pragma once
// Eye-tracking gaze data: the dataset model (participants x stimuli x recordings of samples), the screen
// geometry that turns pixels into degrees of visual angle, and the event types.
//
// Units, everywhere in this folder:
//  - time: milliseconds (double) on the tracker's own clock, converted from whatever the file uses
//    (EyeLink: ms; SMI, Tobii SDK, GazeCom ARFF, DSF coord: µs; see ingest.hpp per format). Absolute
//    clocks are kept (not shifted to 0), so tracker events and messages stay on the same time base.
//  - position: screen pixels, origin top-left, x right, y down (Recording::units == Units::px), or degrees
//    of visual angle from the screen centre, x right, y down (Units::deg: GazeBase-style files). Files with
//    another convention (SimpleGazeTracker's bottom-left origin, PsychoPy's centred y-up pixels, Tobii's
//    normalised 0-1 coordinates) are converted on ingest.
//  - geometry: screen size in pixels and centimetres, viewing distance (eye to screen) in centimetres.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace trailscope::gaze {

/// The screen the gaze was recorded on. A field of 0 is unknown. Pixels alone allow px-space views;
/// degrees of visual angle need all five fields.
struct ScreenGeometry {
  double width_px = 0, height_px = 0;
  double width_cm = 0, height_cm = 0;
  double distance_cm = 0;  ///< eye to screen
  bool has_pixels() const noexcept { return width_px > 0 && height_px > 0; }
  bool has_physical() const noexcept {
    return has_pixels() && width_cm > 0 && height_cm > 0 && distance_cm > 0;
  }
  /// `given` fields that are non-zero replace this one's (a caller's values override the file's).
  ScreenGeometry overridden_by(const ScreenGeometry& given) const noexcept;
};

/// Converts screen pixels (origin top-left, y down) to degrees of visual angle from the screen centre, per
/// axis: deg = atan((px - size_px / 2) * size_cm / size_px / distance_cm), x right, y down. This is the
/// per-axis form common in gaze toolboxes (e.g. remodnav's px2deg uses its small-angle version); it is exact
/// on the two axes through the centre and good to < 1 % within 20 degrees of it. Throws
/// Error(invalid_argument, "geometry", ...) when `g` lacks a physical size or distance.
double px_to_deg_x(double x_px, const ScreenGeometry& g);
double px_to_deg_y(double y_px, const ScreenGeometry& g);

enum class Units : std::uint8_t { px, deg };
const char* to_string(Units u) noexcept;

/// Event types; the numeric codes are those of the Lund 2013 hand-coded data (Andersson, Larsson,
/// Holmqvist, Stridh and Nystrom, Behav Res Methods 2017), so their labels can be used directly.
enum class EventType : std::uint8_t {
  none = 0,      ///< not classified (also: outside every detected event)
  fixation = 1,  ///< gaze held still on a target
  saccade = 2,   ///< fast jump between fixations
  pso = 3,       ///< post-saccadic oscillation ("glissade")
  pursuit = 4,   ///< smooth pursuit of a moving target
  blink = 5,     ///< eye closed / signal lost (includes every invalid sample in detector output)
  undefined = 6  ///< a coder's "cannot say"
};
const char* to_string(EventType t) noexcept;

/// An event reported by the tracker itself (EyeLink EFIX/ESACC/EBLINK) or by a detector: samples with
/// t_start_ms <= t <= t_end_ms. `eye` is 'L', 'R' or 0 (not eye-specific / binocular average).
struct GazeEvent {
  EventType type = EventType::none;
  char eye = 0;
  double t_start_ms = 0, t_end_ms = 0;
};

/// One continuous recording: one trial (EyeLink START..END block, SMI trial, SimpleGazeTracker
/// #START_REC block, PsychoPy-Tobii session) or one whole file. Samples are in file order (times
/// non-decreasing in every file seen so far, but not required); invalid samples (tracker lost the eye,
/// blink, the file's missing-value marker) are kept with valid = 0 and x = y = NaN, so the sample count
/// equals the file's.
struct Recording {
  std::string participant;  ///< from the file (SMI "Subject") or the caller; may be empty
  std::string stimulus;     ///< from the file (SMI "Scene Image", EyeLink "!V IMGLOAD") or the caller
  std::string trial;   ///< block/trial id within the file (the EyeLink TRIALID text, ...; else "1", "2", ...)
  std::string format;  ///< the reader that produced it (ingest.hpp to_string(GazeFormat))
  Units units = Units::px;
  ScreenGeometry geometry;
  double rate_hz = 0;  ///< nominal sampling rate from the file; 0 when the file does not say
  std::vector<double> t_ms;
  std::vector<double> x, y;               ///< in `units`; NaN when invalid
  std::vector<std::uint8_t> valid;        ///< 1 valid, 0 invalid
  std::vector<GazeEvent> tracker_events;  ///< the tracker's own online events (EyeLink), time-ordered
  /// Per-sample label columns carried by the file (Lund TSV "label_MN", GazeBase "lab"), name -> one
  /// integer per sample (EventType codes where the file uses them).
  std::vector<std::pair<std::string, std::vector<int>>> annotations;

  std::size_t size() const noexcept { return t_ms.size(); }
  std::size_t valid_count() const noexcept;
  /// Gaze in degrees of visual angle (a copy when units == deg, else px_to_deg_*; invalid stays NaN).
  /// Throws Error(invalid_argument, "geometry", ...) when px and the geometry has no physical size.
  void degrees(std::vector<double>& x_deg, std::vector<double>& y_deg) const;
};

/// A gaze dataset: recordings, each tagged with participant and stimulus (participants x stimuli x
/// recordings; one participant may see a stimulus more than once).
struct GazeDataset {
  std::vector<Recording> recordings;
  std::size_t total_samples() const noexcept;
  /// Distinct non-empty participants / stimuli, sorted.
  std::vector<std::string> participants() const;
  std::vector<std::string> stimuli() const;
};

}  // namespace trailscope::gaze
