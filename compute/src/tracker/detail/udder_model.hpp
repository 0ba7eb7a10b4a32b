#pragma once
// Stage 4 of the tracker: which verified candidate is which teat. The udder model is the four teats'
// pairwise distances and radii, learnt while tracking; assignments are found by exhaustive search
// (at most kMaxModelCandidates candidates, so at most 11^4 labellings). Internal.
#include <array>
#include <optional>
#include <vector>

#include <Eigen/Dense>

#include "trailscope/tracker/tracker.hpp"

namespace trailscope::tracker::detail {

inline constexpr int kMaxModelCandidates = 10;

struct ModelCandidate {
  Eigen::Vector3d tip;
  double u = 0, v = 0;  ///< tip projection, px
  double ncc = 0;
  double radius = 0;
  Eigen::Vector3d axis = Eigen::Vector3d::Zero();  ///< unit, tip towards base
};

struct UdderModel {
  std::array<double, 6> dist{};    ///< kTeatPairs distances, mm; NaN = not learnt
  std::array<double, 4> radius{};  ///< mm; 0 = not learnt
  UdderModel();
  bool knows_shape() const;
  /// Whether a candidate of radius r_mm may be teat t: any radius while t's is not learnt, else one within
  /// p.radius_tol_mm of it.
  bool radius_fits(int t, double r_mm, const TrackerParams& p) const;
};

/// Candidate index per teat (-1 = none).
using Labelling = std::array<int, 4>;

/// Acquisition (SEARCH, LOST, and recovery after a jump): the labelling with the most teats (at least
/// `min_count`), then the lowest model cost, whose pair spacings are plausible, whose image layout is
/// that of an udder seen from behind and below (front teats lower in the image than rear ones, left
/// teats left of right ones), and which fits the learnt model where it is known (each pair within
/// model_max, each radius within radius_tol). Empty when none qualifies.
std::optional<Labelling> acquire(const std::vector<ModelCandidate>& c, const UdderModel& m,
                                 const TrackerParams& p, int min_count);

/// Tracking: each tracked teat (prediction given) takes the candidate that minimises gate distance plus
/// NCC penalty, within d_gate and radius_tol, jointly (no candidate serves two teats).
Labelling assign_tracked(const std::vector<ModelCandidate>& c,
                         const std::array<std::optional<Eigen::Vector3d>, 4>& pred, const UdderModel& m,
                         const TrackerParams& p);

/// Model metrics of a labelling (ModelMetrics in tracker.hpp).
ModelMetrics model_metrics(const std::vector<ModelCandidate>& c, const Labelling& l, const UdderModel& m,
                           const TrackerParams& p);

/// Blends the observed pair distances and radii into the model (rate 1 for unknown entries).
void learn(UdderModel& m, const std::vector<ModelCandidate>& c, const Labelling& l, double rate);

}  // namespace trailscope::tracker::detail
