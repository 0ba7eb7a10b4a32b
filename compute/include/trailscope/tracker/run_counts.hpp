#pragma once
// How a run's frames divide among the tracker's states, and the tracker's own time: the figures every
// summary of a run starts from (the run store's rows, `trailscope track`, run comparisons).
#include <cstddef>
#include <vector>

#include "trailscope/tracker/tracker.hpp"

namespace trailscope::tracker {

struct StateCounts {
  std::size_t search = 0, track = 0, lost = 0;  ///< frames in each state
  std::size_t lost_episodes = 0;                ///< maximal runs of consecutive LOST frames
  double tracker_us = 0;                        ///< sum of the frames' stage times (µs)
};

StateCounts count_states(const std::vector<FrameLog>& frames);

}  // namespace trailscope::tracker
