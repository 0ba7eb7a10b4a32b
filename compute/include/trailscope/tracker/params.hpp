#pragma once
// Parameters of the teat detector and tracker (tracker.hpp), each with its unit, default and range. A run's
// full parameter vector is logged with it (tracker_log.hpp), swept by parameter studies and projected as a
// point in parameter space, so every parameter is a plain number.
#include <string>
#include <string_view>
#include <vector>

#include "trailscope/core/params.hpp"

namespace trailscope::tracker {

struct TrackerParams {
  // --- preprocessing ---
  double a_min = 40;      ///< amplitude below which a pixel is invalid (camera units), 0..10000
  double z_min_mm = 80;   ///< depth gate near end, mm, 0..5000
  double z_max_mm = 900;  ///< depth gate far end, mm, 1..10000, > z_min_mm
  double flying_mm = 18;  ///< a pixel farther than this from its 3x3 median is a flying pixel, mm, 1..500
  int median_k = 3;       ///< median filter window on depth (1 = off), 1, 3 or 5
  // --- candidate detection (NCC with a bank of rounded-tip depth templates) ---
  int templates = 4;            ///< templates in the bank, 1..8
  double template_min_px = 3;   ///< tip radius of the smallest template, px, 1.5..40
  double template_max_px = 12;  ///< tip radius of the largest template (radii spaced geometrically), px
  /// NCC score a match needs, 0..1. A front teat seen from the side on a far udder (the camera low behind
  /// the cow) correlates with the rounded-tip templates at 0.3-0.45, below 0.35 in most frames, and the
  /// first acquisition waits for all four teats: 0.35 left cups-attached seed 2001 searching for its first
  /// 108 frames. The 3D fit rejects what the lower score lets in (tracker 1.4: 0.25; see the README).
  /// Inside TRACK windows a match needs at least 0.3 (tracker.cpp, kTrackWindowNcc).
  double ncc_min = 0.25;
  /// NCC matches kept per frame (best first), 1..200. Each costs a 3D fit, and beyond the tenth they are
  /// clutter: a noisy whole frame has ~18. Keeping 10 instead of 24 made the noisy synthetic scenario
  /// faster with a lower median tip error (seeds 1-5) and left the other scenarios' results unchanged.
  int max_candidates = 10;
  // --- 3D verification (capsule fit to the point cloud around a match) ---
  double r_min_mm = 6;         ///< plausible teat radius, mm, 1..100
  double r_max_mm = 17;        ///< mm, > r_min_mm
  double fit_rms_mm = 4.5;     ///< largest RMS residual of an accepted fit, mm, 0.1..50
  double fit_reach_mm = 24;    ///< points within this distance of the tip belong to the fit, mm, 5..200
  double radius_tol_mm = 3.5;  ///< in TRACK, a teat's candidate radius may differ this much from its own, mm
  // --- four-teat model ---
  double spacing_min_mm = 45;   ///< smallest plausible distance between two teats, mm, 1..1000
  double spacing_max_mm = 260;  ///< largest, mm, > spacing_min_mm
  double w_shape = 1.0;         ///< weight of the pair-distance error in the model cost, 0..100
  double w_ncc = 20.0;          ///< weight of (1 - NCC) in the model cost (mm per unit), 0..1000
  double model_max = 22;        ///< largest accepted model cost, mm, 0..1000
  // --- state machine and Kalman filter ---
  double d_gate_mm = 22;  ///< a teat's match must lie within this distance of its prediction, mm, 1..500
  int n_lost = 4;         ///< frames with fewer than min_teats matched before TRACK turns LOST, 1..1000
  int n_confirm = 2;      ///< consistent SEARCH frames before TRACK, 1..1000
  /// Teats a frame needs matched to count as tracked, 1..4 (in TRACK a single teat matched within half
  /// the gate of its prediction also counts).
  int min_teats = 2;
  /// Process noise: acceleration spectral density, mm/s^2, 0..1e7. A teat under a swaying udder changes
  /// velocity within a few frames; 4000 (up to tracker 1.3) made the filtered tip lag 8-13 mm behind a
  /// fast-motion udder. 1e5 follows it and still smooths the fit's noise (tracker 1.4; see the README).
  double kalman_q = 1e5;
  double kalman_r_mm = 1.5;  ///< measurement noise standard deviation, mm, 0.01..100
};

/// Every parameter, in a stable order (the order of the logged vector). All are numeric: the CLI and the
/// API show unit, default_number, min, max and integer.
const std::vector<ParamInfo>& parameter_infos();

/// The parameter vector in parameter_infos() order.
std::vector<double> to_vector(const TrackerParams& p);
/// Reads a value by name. Throws Error(invalid_argument, name) for an unknown name.
double get_param(const TrackerParams& p, std::string_view name);
/// Sets a value by name (integers must be whole). Throws Error(invalid_argument, name) for an unknown
/// name, a non-finite or fractional value, or one outside its range.
void set_param(TrackerParams& p, std::string_view name, double value);
/// Checks every range and the cross-constraints (z_min < z_max, r_min < r_max, template_min <= max,
/// spacing_min < spacing_max, median_k odd). Throws Error(invalid_argument, name of the parameter).
void validate(const TrackerParams& p);

}  // namespace trailscope::tracker
