#pragma once
// Teat detector and tracker for low-resolution time-of-flight depth video (van der Zwan & Telea, "Robust
// and Fast Teat Detection and Tracking in Low-resolution Videos for Automatic Milking Devices", VISAPP
// 2015). The paper gives the task and its inputs, not its matcher or thresholds: the stages below are
// our design. Per frame:
//   1. preprocess: amplitude gate, depth gate, flying-pixel removal (distance to the 3x3 median), median;
//   2. detect: NCC of the depth image with a bank of rounded-tip templates (teat tips point at the camera,
//      so they are local depth protrusions); local NCC maxima >= ncc_min are the "matches";
//   3. verify: fit a capsule end (sphere of radius r on an axis) to the point cloud around each match by
//      robust Gauss-Newton; keep fits with r in [r_min, r_max] and a small residual; the 3D tip is the
//      apex of the fitted end, sphere centre - r * axis;
//   4. model: assign verified candidates to the four teats (FL, FR, RL, RR) by the udder model: in SEARCH
//      by the quadrilateral's layout in the image and plausible spacings, in TRACK by gating to each
//      teat's Kalman prediction and scoring the six pair distances against the tracked model;
//   5. state: SEARCH -> TRACK after n_confirm consistent frames; TRACK -> LOST when fewer than min_teats
//      teats are matched (or the model cost exceeds model_max) for n_lost frames; LOST searches again.
// Units: mm and camera coordinates as in tof/depth_video.hpp; px with pixel-centre (0,0).
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string_view>
#include <vector>

#include "trailscope/tof/depth_video.hpp"
#include "trailscope/tracker/params.hpp"

namespace trailscope::tracker {

/// Tracker version written into every log; bump when results change.
inline constexpr std::string_view kTrackerVersion = "trailscope-tracker 1.4";

enum class State { search, track, lost };
std::string_view to_string(State s);  ///< "SEARCH", "TRACK", "LOST"
/// Inverse of to_string (case-insensitive). Throws Error(invalid_argument, "state").
State parse_state(std::string_view s);

/// One NCC match and its 3D verification.
struct Candidate {
  double u = 0, v = 0;             ///< match position, px
  double ncc = 0;                  ///< NCC score, -1..1
  int template_index = 0;          ///< which template of the bank matched best
  bool verified = false;           ///< the capsule fit passed
  std::array<double, 3> tip_mm{};  ///< fitted apex (camera coordinates, mm); meaningful when verified
  std::array<double, 3> axis{};    ///< unit axis from the tip towards the teat base; when verified
  double radius_mm = 0;            ///< fitted radius, mm (0 when the fit failed)
  double fit_rms_mm = 0;           ///< RMS residual of the fit, mm
  int points = 0;                  ///< points used by the fit
  int teat = -1;                   ///< teat it was assigned to (0..3, kTeatNames order), -1 = none
};

/// Pairs of teats in the order the model metrics use: FL-FR, RL-RR, FL-RL, FR-RR, FL-RR, FR-RL.
inline constexpr std::array<std::array<int, 2>, 6> kTeatPairs = {
    {{0, 1}, {2, 3}, {0, 2}, {1, 3}, {0, 3}, {1, 2}}};

/// The udder-model metrics of a frame's assignment ("model metrics" in the paper's frame-data view).
struct ModelMetrics {
  std::array<double, 6> pair_mm{};  ///< distance of each kTeatPairs pair, mm; NaN when a teat is missing
  std::array<double, 6> pair_error_mm{};  ///< |distance - model's distance|, mm; NaN when unknown
  double shape_cost = 0;                  ///< mean pair error, mm (0 when fewer than two teats)
  double ncc_cost = 0;                    ///< mean (1 - NCC) of the matched teats
  double cost = 0;                        ///< w_shape * shape_cost + w_ncc * ncc_cost
  int teats_matched = 0;                  ///< teats with a verified candidate this frame
};

/// What the tracker reports for one teat in one frame.
struct TeatEstimate {
  std::array<double, 3>
      tip_mm{};  ///< estimated tip, camera coordinates, mm (the prediction when not visible)
  std::array<double, 2> tip_px{};  ///< its projection, px
  bool visible = false;            ///< matched and verified this frame
  bool tracked = false;            ///< the teat has a track (position meaningful)
  double confidence = 0;           ///< 0..1: NCC and fit quality when visible, decaying while predicted
  double radius_mm = 0;            ///< the teat's tracked radius, mm
};

/// Wall time of each stage for this frame, microseconds (not deterministic; excluded from comparisons).
struct StageTimes {
  double preprocess_us = 0, detect_us = 0, verify_us = 0, model_us = 0;
  double total_us() const { return preprocess_us + detect_us + verify_us + model_us; }
};

/// Everything the tracker decided in one frame: the per-frame record of a tracker log.
struct FrameLog {
  std::size_t index = 0;
  double timestamp_s = 0;
  /// Pixels that passed every gate, and those removed as flying pixels. In TRACK only the search
  /// windows around the predictions are prepared, so these count within the windows.
  int valid_pixels = 0;
  int flying_pixels = 0;
  int matches = 0;   ///< NCC matches (local maxima >= ncc_min) before verification
  int verified = 0;  ///< candidates whose 3D fit passed
  std::vector<Candidate> candidates;
  ModelMetrics model;
  State state = State::search;
  std::array<TeatEstimate, tof::kTeatCount> teats{};
  StageTimes times;
};

/// Stateful tracker over one video. Not thread-safe; one per video.
class Tracker {
 public:
  /// Throws Error(invalid_argument, name) for bad parameters (validate) or intrinsics.
  Tracker(const TrackerParams& params, const tof::Intrinsics& intrinsics);
  ~Tracker();
  Tracker(Tracker&&) noexcept;
  Tracker& operator=(Tracker&&) noexcept;

  /// Processes the next frame (frames in time order). Throws Error(invalid_argument, "frame") when the
  /// image size does not match the intrinsics. Frames without amplitude skip the amplitude gate.
  FrameLog process(const tof::DepthFrame& frame);
  /// Forgets all tracks (back to SEARCH) and the frame counter.
  void reset();
  const TrackerParams& params() const;

  /// The template bank as depth offsets (mm-free: NCC is invariant to scale), for logs and the dashboard:
  /// per template its radius in px and its size (odd, px).
  struct TemplateInfo {
    double radius_px = 0;
    int size_px = 0;
  };
  std::vector<TemplateInfo> templates() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace trailscope::tracker
