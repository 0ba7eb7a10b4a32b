// Fixations and saccades placed on the stimulus (fixations.hpp).
#include "trailscope/gazeview/fixations.hpp"

#include <string>

#include "trailscope/core/error.hpp"

namespace trailscope::gazeview {

std::vector<std::size_t> pixel_recordings(const gaze::GazeDataset& ds, const gaze::GazeFilter& f) {
  std::vector<std::size_t> sel = gaze::select_recordings(ds, f);
  for (std::size_t i : sel)
    if (ds.recordings[i].units != gaze::Units::px)
      throw invalid_argument("recording", "recording " + std::to_string(i) +
                                              " is in degrees of visual angle; stimulus views need pixels");
  return sel;
}

ViewEvents view_events(const gaze::GazeDataset& ds, const gaze::GazeFilter& f, const gaze::EventParams& p,
                       std::size_t max_events) {
  ViewEvents out;
  out.recordings = pixel_recordings(ds, f);
  const gaze::EventList list =
      gaze::list_events(ds, f, p, {gaze::EventType::fixation, gaze::EventType::saccade}, max_events);
  for (const gaze::EventRow& e : list.events) {
    const double t0 = ds.recordings[e.recording].t_ms.front();
    if (e.type == gaze::EventType::fixation)
      out.fixations.push_back(
          {e.recording, e.t_start_ms, e.t_end_ms, e.t_start_ms - t0, e.t_end_ms - e.t_start_ms, e.x, e.y});
    else
      out.saccades.push_back(
          {e.recording, e.t_start_ms, e.t_end_ms, e.t_start_ms - t0, e.x, e.y, e.x_end, e.y_end});
  }
  return out;
}

}  // namespace trailscope::gazeview
