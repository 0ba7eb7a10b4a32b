#pragma once
// Gaze events placed on the stimulus, as the gaze views (AOI statistics, stimulus-space density tiles,
// saccade bundling) read them: the fixations (centroid, duration) and saccades (start, end) of the
// recordings a gaze::GazeFilter selects (gaze/query.hpp: the one selection of every gaze view, window
// [t0_ms, t1_ms) after each recording's first sample, an event in it when its first sample is; events
// detected on the whole recording).
//
// Units: positions in stimulus = screen pixels, origin top-left, x right, y down (gaze/gaze.hpp): the
// stimulus is taken to fill the screen from its top-left corner, as in the shared Lund data (1024 x 768
// images on a 1024 x 768 screen). Times in ms: `t_start_ms`/`t_end_ms` on the tracker clock, `onset_ms`
// from the recording's first sample. Positions and durations are gaze::list_events' (a fixation at the
// mean of its samples, duration t_end − t_start; a saccade from its first valid sample to its last).
#include <cstddef>
#include <vector>

#include "trailscope/gaze/events.hpp"
#include "trailscope/gaze/gaze.hpp"
#include "trailscope/gaze/query.hpp"

namespace trailscope::gazeview {

struct Fixation {
  std::size_t recording = 0;  ///< index of its recording in the dataset
  double t_start_ms = 0, t_end_ms = 0;
  double onset_ms = 0;  ///< t_start_ms − the recording's first sample time
  double duration_ms = 0;
  double x = 0, y = 0;  ///< centroid, stimulus px
};

struct Saccade {
  std::size_t recording = 0;
  double t_start_ms = 0, t_end_ms = 0;
  double onset_ms = 0;
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< first and last valid sample, stimulus px
};

/// The recordings `f` selects (gaze::select_recordings and its errors), each checked to be in pixels:
/// Error(invalid_argument, "recording", "recording N is in degrees of visual angle; stimulus views need
/// pixels") otherwise.
std::vector<std::size_t> pixel_recordings(const gaze::GazeDataset& ds, const gaze::GazeFilter& f);

struct ViewEvents {
  std::vector<std::size_t> recordings;  ///< pixel_recordings(ds, f)
  std::vector<Fixation> fixations;      ///< recording by recording (ascending), each in time order
  std::vector<Saccade> saccades;
};

/// The fixations and saccades of the selection: pixel_recordings, then gaze::list_events with `p` for
/// those two types (its errors: detector parameters, geometry, and Error(payload_too_large, "events",
/// ...) when more than `max_events` fixations and saccades together would be returned).
ViewEvents view_events(const gaze::GazeDataset& ds, const gaze::GazeFilter& f, const gaze::EventParams& p,
                       std::size_t max_events);

}  // namespace trailscope::gazeview
