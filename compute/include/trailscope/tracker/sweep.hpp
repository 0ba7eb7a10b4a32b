#pragma once
// Parameter sweeps: the points of parameter space a study runs the tracker at — a full grid over a few
// parameters, or a uniform random sample over many (random search covers high-dimensional spaces far
// better than a grid of the same size). Every other parameter keeps its base value. run_sweep runs the
// tracker at every point on every video of a study.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trailscope/core/progress.hpp"
#include "trailscope/tracker/params.hpp"
#include "trailscope/tracker/tracker_log.hpp"

namespace trailscope::tracker {

struct SweepAxis {
  std::string param;        ///< a parameter_infos() name
  double min = 0, max = 0;  ///< inclusive, within the parameter's range
  int steps = 5;            ///< grid values along this axis (2..100; ignored by random sampling)
};

enum class SweepMode { grid, random };

struct SweepSpec {
  TrackerParams base;
  std::vector<SweepAxis> axes;  ///< 1..parameter_infos().size(), each parameter at most once
  SweepMode mode = SweepMode::random;
  std::size_t samples = 200;  ///< random: number of points, 1..limits::kMaxSweepRuns
  std::uint64_t seed = 1;
};

/// The points, in a stable order (grid: the first axis varies slowest). Integer parameters are rounded
/// (grid duplicates after rounding are kept once); a random point that breaks a cross-constraint
/// (validate(), e.g. r_min_mm >= r_max_mm) is drawn again (at most 100 times per point, then
/// Error(unprocessable, "axes")). Throws Error(invalid_argument, "axes") for an unknown or repeated
/// parameter, a range outside the parameter's own or min > max, steps out of range; Error(payload_too_large,
/// "axes") when the grid or sample exceeds limits::kMaxSweepRuns; Error(invalid_argument, "samples").
std::vector<TrackerParams> sweep_points(const SweepSpec& spec);

/// {"mode": "grid"|"random", "samples": N, "seed": S, "base": {name: value}, "axes": [{"param", "min",
/// "max", "steps"}]} — the body of POST /api/v1/sweeps. Throws Error(invalid_argument, field) naming the
/// field at fault.
SweepSpec parse_sweep(const nlohmann::json& j);
nlohmann::json to_json(const SweepSpec& spec);

/// One video of a sweep: its id (RunHeader::video_id of its runs) and its file (any DepthVideoReader source).
struct SweepVideo {
  std::string id;
  std::filesystem::path path;
};

/// Runs the tracker at every point on every video (points outermost: all videos of the first point, then
/// the second...), over the frames `range` gives (its first_frame and frame_count; run_id and video_id
/// are set per run), and hands each finished log to `on_run` (which stores it) before the next starts.
/// Progress ("sweep") is the fraction of all points.size() x videos.size() runs, within a run too.
/// `cancel` is checked before each run and at every progress report of a run: Error(cancelled) then
/// stops the sweep, and the run under way is not handed on. Throws what run_tracker and on_run throw.
void run_sweep(const std::vector<TrackerParams>& points, const std::vector<SweepVideo>& videos,
               const RunOptions& range, const std::function<void(TrackerLog&&)>& on_run,
               const ProgressFn& progress = {}, const CancelToken* cancel = nullptr);

}  // namespace trailscope::tracker
