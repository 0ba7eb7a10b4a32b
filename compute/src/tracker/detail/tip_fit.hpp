#pragma once
// Stage 3 of the tracker: 3D verification of an NCC match. A teat ends in a rounded tip, so the point
// cloud around a match should fit a capsule end — a hemisphere of radius r on a cylinder of the same
// radius along axis a. The fit (robust Gauss-Newton with Levenberg damping over centre c, axis a and r)
// gives the tip as the apex c - r a: the point where the teat axis leaves the surface, which is what the
// robot aims the cup at and what the ground truth marks, whereas the point nearest the camera slides
// around the tip as the viewing angle changes. Internal.
#include <array>
#include <optional>

#include "tracker/detail/frame_prep.hpp"
#include "trailscope/tof/depth_video.hpp"
#include "trailscope/tracker/params.hpp"

namespace trailscope::tracker::detail {

struct TipFit {
  bool ok = false;  ///< converged with enough points (verification criteria are applied by the caller)
  std::array<double, 3> tip{};     ///< apex, mm
  std::array<double, 3> centre{};  ///< centre of the tip hemisphere, mm
  std::array<double, 3> axis{};    ///< unit, from the tip towards the base
  double radius = 0;               ///< mm
  double rms = 0;                  ///< RMS residual (clipped at 3 Huber widths), mm
  int points = 0;
};

/// What the tracker already knows about the teat, used as weak priors (tracked teats only).
struct TipPrior {
  double radius_mm = 0;          ///< 0 = unknown
  std::array<double, 3> axis{};  ///< zero = unknown
};

/// Fits the tip near pixel (u, v) (a match at template radius `radius_px`).
TipFit fit_tip(const PreparedFrame& f, const tof::Intrinsics& k, double u, double v, double radius_px,
               const TrackerParams& p, const TipPrior& prior = {});

}  // namespace trailscope::tracker::detail
