#pragma once
// Fixation and saccade detection on one gaze Recording (gaze.hpp), and sample-level agreement (Cohen's
// kappa) between two labelings.
//
// Every detector works in degrees of visual angle (Recording::degrees(): the recording needs a physical
// screen geometry unless it is already in degrees) and on time in ms, and returns one label per sample:
//  - invalid samples (Recording::valid == 0) are EventType::blink in every method: the tracker lost the
//    eye, and blink / signal loss is what the hand-coded reference data call such samples;
//  - I-VT: Salvucci and Goldberg, "Identifying fixations and saccades in eye-tracking protocols", ETRA
//    2000. A sample whose point-to-point angular velocity exceeds the threshold is a saccade, any other
//    valid sample a fixation; fixation runs shorter than min_fixation_ms become EventType::none.
//  - I-DT: the same paper's dispersion-threshold identification. A window of at least min_duration_ms
//    whose dispersion (max x - min x) + (max y - min y) is at most the threshold starts a fixation, which
//    grows while the dispersion stays within it; samples left outside every fixation are saccades. A window
//    never spans an invalid sample.
//  - adaptive: Nystrom and Holmqvist, "An adaptive algorithm for fixation, saccade, and glissade detection
//    in eyetracking data", Behav Res Methods 42(1), 2010. Velocity from a Savitzky-Golay derivative; the
//    peak threshold PT iterates PT <- mean + 6 sd of the velocities below PT until it moves less than
//    1 deg/s; saccades are runs around peaks above PT from the onset (velocity below mean + 3 sd and
//    falling, walking back) to the offset (below 0.7 onset + 0.3 local noise threshold and falling);
//    post-saccadic oscillations (glissades, EventType::pso) are velocity above the offset threshold within
//    the glissade window after a saccade; what remains in runs of at least min_fixation_ms is fixation.
//    Samples above the physiological maximum velocity or acceleration are noise, labelled like invalid
//    samples (blink), as in the paper.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "trailscope/gaze/gaze.hpp"

namespace trailscope::gaze {

enum class Method { ivt, idt, adaptive };
const char* to_string(Method m) noexcept;
/// "ivt" | "idt" | "adaptive"; throws Error(invalid_argument, param, ...) otherwise.
Method parse_method(std::string_view text, const std::string& param = "method");

struct IvtParams {
  /// Saccade above this point-to-point velocity (deg/s), (0, 5000]. 30 deg/s is the common default (the
  /// Tobii I-VT filter's, and in the range Salvucci and Goldberg discuss).
  double velocity_threshold_deg_s = 30;
  /// Fixation runs shorter than this (ms) are left unclassified, [0, 10000]; 0 keeps every run.
  double min_fixation_ms = 0;
};

struct IdtParams {
  /// Largest (max x - min x) + (max y - min y) of a fixation window (deg), (0, 100].
  double dispersion_threshold_deg = 1.0;
  /// Shortest fixation (ms), (0, 10000]; also the initial window. 100 ms as in Salvucci and Goldberg.
  double min_duration_ms = 100;
};

struct AdaptiveParams {
  /// Initial peak velocity threshold PT (deg/s), (0, 1000]; the paper starts at 100-300.
  double initial_peak_threshold_deg_s = 100;
  /// Savitzky-Golay derivative window (ms), [2 samples' time, 1000]; the paper uses about 20 ms.
  double filter_window_ms = 20;
  /// Shortest saccade (ms), [0, 1000]; shorter candidates stay unclassified samples.
  double min_saccade_ms = 10;
  /// Shortest fixation (ms), [0, 10000].
  double min_fixation_ms = 40;
  /// Window after a saccade's offset in which a glissade may occur (ms), [0, 1000].
  double glissade_window_ms = 40;
  /// Faster samples are noise (treated as invalid), deg/s, (0, 10000].
  double max_velocity_deg_s = 1000;
  /// Samples whose speed changes faster than this are noise too (deg/s^2), (0, 10000000]; the paper's
  /// 100,000 deg/s^2.
  double max_acceleration_deg_s2 = 100000;
};

struct EventParams {
  Method method = Method::ivt;
  IvtParams ivt;
  IdtParams idt;
  AdaptiveParams adaptive;
};

/// Throws Error(invalid_argument, "<field name>", ...) when a parameter is outside its range above.
void validate(const EventParams& p);

struct Detection {
  std::vector<EventType> labels;  ///< one per sample of the recording
  std::vector<GazeEvent> events;  ///< runs of equal labels other than none, in time order (eye 0)
  /// adaptive: the final peak and onset thresholds (deg/s); I-VT: the threshold twice; I-DT: NaN.
  double peak_threshold_deg_s = 0, onset_threshold_deg_s = 0;
};

/// Labels every sample of `r`. Throws Error(invalid_argument, "geometry", ...) when the recording is in
/// px without a physical geometry, validate()'s errors, and Error(invalid_argument, "min_duration_ms",
/// ...) when an I-DT window would exceed limits::kMaxGazeWindowSamples samples (adaptive: the same for
/// "filter_window_ms" and "glissade_window_ms"). Samples need not be
/// equally spaced (time steps are used as they are; the Savitzky-Golay window uses the median step), but
/// their times must be finite and must not decrease: Error(unprocessable, "file", ...) names the first
/// sample that breaks this. Runs in time linear in the samples for every method.
Detection detect_events(const Recording& r, const EventParams& p);

/// Angular velocity per sample (deg/s): the central difference over the neighbouring valid samples
/// (one-sided at ends and next to invalid samples); NaN for invalid samples and for valid samples with no
/// valid neighbour. Input in degrees, time in ms.
std::vector<double> point_velocity(const std::vector<double>& t_ms, const std::vector<double>& x_deg,
                                   const std::vector<double>& y_deg, const std::vector<std::uint8_t>& valid);

/// Cohen's kappa (Cohen, "A coefficient of agreement for nominal scales", Educ Psychol Meas 20, 1960) of
/// two labelings for one event type, each sample reduced to "is `type`" or not:
/// (p_o - p_e) / (1 - p_e). NaN when the sizes differ or are 0, or when p_e == 1 (both labelings
/// constant, kappa undefined).
double cohen_kappa(const std::vector<EventType>& a, const std::vector<EventType>& b, EventType type);

/// Runs of equal labels (other than none) as events with their first and last sample times.
std::vector<GazeEvent> label_runs(const std::vector<double>& t_ms, const std::vector<EventType>& labels);

}  // namespace trailscope::gaze
