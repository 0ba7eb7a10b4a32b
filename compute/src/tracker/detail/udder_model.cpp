#include "tracker/detail/udder_model.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>

namespace trailscope::tracker::detail {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Model-cost millimetres one unit of layout score is worth when choosing among labellings.
constexpr double kLayoutWeight = 5.0;
// Layout-score units per kAnatomyScaleMm by which the front pair is wider than the rear pair (layout_score).
// 0.3: of 0.2, 0.3 and 0.5, the smallest that labelled every `occluded` video of seeds 2000-2039 right with
// the synthetic camera's lock-in sensor model (synth.hpp, kSynthCamera "trailscope-tof 2"); 0.2 left one
// (2039) a quarter turn off. Without the term six of the forty were off; with the camera's earlier Gaussian
// depth noise 0.2 had been the smallest of 0.1, 0.2, 0.3, 0.5 (tracker 1.2). On seeds 2000-2009 of the
// other scenarios 0.2 and 0.3 give the same shares. Seeds 1000-1019, the robustness benchmark's, were not
// used to choose it.
constexpr double kAnatomyWeight = 0.3, kAnatomyScaleMm = 40.0;

// The layout of an udder seen from behind and below, robust to the camera turning about its axis by up
// to 45 degrees: going FL -> FR -> RR -> RL the labelled teats form a convex polygon turning one way in
// the image (the camera never sees the udder mirrored), the front teats lie lower in the image than the rear
// ones on average, and the left teats lie left of the right ones on average.
bool layout_ok(const std::vector<ModelCandidate>& c, const Labelling& l) {
  static constexpr std::array<int, 4> cycle = {0, 1, 3, 2};  // FL, FR, RR, RL
  std::array<int, 4> seq{};
  int n = 0;
  for (int t : cycle)
    if (l[t] >= 0) seq[n++] = l[t];
  if (n == 0) return false;
  // Every corner turns the same way: a convex polygon, not a crossed one.
  for (int i = 0; n >= 3 && i < n; ++i) {
    const auto& a = c[seq[i]];
    const auto& b = c[seq[(i + 1) % n]];
    const auto& d = c[seq[(i + 2) % n]];
    const double turn = (b.u - a.u) * (d.v - b.v) - (b.v - a.v) * (d.u - b.u);
    if (!(turn < 0)) return false;
  }
  return true;
}

// How upright the labelling looks, about -2..2: front teats below rear ones and right teats right of left
// ones, in units of the labelled teats' mean spacing. The four rotations of a convex labelling all pass
// layout_ok; this picks the one closest to the camera's usual roll.
double layout_score(const std::vector<ModelCandidate>& c, const Labelling& l) {
  const auto mean = [&](std::initializer_list<int> ts, bool use_v, double& out) {
    double s = 0;
    int k = 0;
    for (int t : ts)
      if (l[t] >= 0) s += use_v ? c[l[t]].v : c[l[t]].u, ++k;
    if (k) out = s / k;
    return k > 0;
  };
  double spacing = 0;
  int pairs = 0;
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b)
      if (l[a] >= 0 && l[b] >= 0)
        spacing += std::hypot(c[l[a]].u - c[l[b]].u, c[l[a]].v - c[l[b]].v), ++pairs;
  if (pairs == 0 || spacing <= 0) return 0.0;
  spacing /= pairs;
  double front = 0, rear = 0, left = 0, right = 0, score = 0;
  if (mean({0, 1}, true, front) && mean({2, 3}, true, rear)) score += (front - rear) / spacing;
  if (mean({0, 2}, false, left) && mean({1, 3}, false, right)) score += (right - left) / spacing;
  // The image alone cannot tell two rotations apart when the udder appears turned by about 45 degrees (an
  // arm that comes in from the side, as in the `occluded` scenario): both then look equally upright, and
  // the tracker followed the teats a quarter turn off. The udder can: the front teats stand wider apart
  // than the rear ones (124 against 84 mm nominally on the synthetic cow, tof/synth/scene.cpp, as on most
  // cows), whatever the roll. Each cow's teats vary by tens of millimetres around that, so the term is
  // weighted to settle near-ties of the image layout, not to overrule a clear one.
  if (l[0] >= 0 && l[1] >= 0 && l[2] >= 0 && l[3] >= 0) {
    const double front_mm = (c[l[0]].tip - c[l[1]].tip).norm(), rear_mm = (c[l[2]].tip - c[l[3]].tip).norm();
    score += kAnatomyWeight * (front_mm - rear_mm) / kAnatomyScaleMm;
  }
  return score;
}

}  // namespace

UdderModel::UdderModel() {
  dist.fill(kNaN);
}

bool UdderModel::knows_shape() const {
  int n = 0;
  for (double d : dist) n += std::isfinite(d);
  return n >= 3;
}

bool UdderModel::radius_fits(int t, double r_mm, const TrackerParams& p) const {
  return !(radius[t] > 0) || std::fabs(r_mm - radius[t]) <= p.radius_tol_mm;
}

ModelMetrics model_metrics(const std::vector<ModelCandidate>& c, const Labelling& l, const UdderModel& m,
                           const TrackerParams& p) {
  ModelMetrics mm;
  double err = 0, ncc = 0;
  int nerr = 0;
  for (int t = 0; t < 4; ++t)
    if (l[t] >= 0) {
      ++mm.teats_matched;
      ncc += 1.0 - std::max(c[l[t]].ncc, 0.0);  // a tip cut by the image border correlates negatively
    }
  for (int i = 0; i < 6; ++i) {
    const auto [a, b] = kTeatPairs[i];
    mm.pair_mm[i] = mm.pair_error_mm[i] = kNaN;
    if (l[a] < 0 || l[b] < 0) continue;
    mm.pair_mm[i] = (c[l[a]].tip - c[l[b]].tip).norm();
    if (std::isfinite(m.dist[i])) {
      mm.pair_error_mm[i] = std::fabs(mm.pair_mm[i] - m.dist[i]);
      err += mm.pair_error_mm[i];
      ++nerr;
    }
  }
  mm.shape_cost = nerr ? err / nerr : 0.0;
  mm.ncc_cost = mm.teats_matched ? ncc / mm.teats_matched : 0.0;
  mm.cost = p.w_shape * mm.shape_cost + p.w_ncc * mm.ncc_cost;
  return mm;
}

std::optional<Labelling> acquire(const std::vector<ModelCandidate>& c, const UdderModel& m,
                                 const TrackerParams& p, int min_count) {
  const int n = std::min<int>(static_cast<int>(c.size()), kMaxModelCandidates);
  std::optional<Labelling> best;
  int best_count = 0;
  double best_cost = std::numeric_limits<double>::infinity();
  Labelling l{-1, -1, -1, -1};
  // Depth-first over teats; pairs are checked as soon as both ends are labelled, which prunes early.
  const auto pair_ok = [&](int t) {
    for (int i = 0; i < 6; ++i) {
      const auto [a, b] = kTeatPairs[i];
      if (std::max(a, b) != t || l[a] < 0 || l[b] < 0) continue;
      const double d = (c[l[a]].tip - c[l[b]].tip).norm();
      if (d < p.spacing_min_mm || d > p.spacing_max_mm) return false;
      if (std::isfinite(m.dist[i]) && std::fabs(d - m.dist[i]) > p.model_max) return false;
    }
    return true;
  };
  const auto visit = [&](auto&& self, int t) -> void {
    if (t == 4) {
      int count = 0;
      for (int x : l) count += x >= 0;
      if (count < min_count || count < best_count || !layout_ok(c, l)) return;
      // Upright labellings first (layout_score), then the model cost.
      const double cost = model_metrics(c, l, m, p).cost - kLayoutWeight * layout_score(c, l);
      if (count > best_count || cost < best_cost) {
        best_count = count;
        best_cost = cost;
        best = l;
      }
      return;
    }
    l[t] = -1;
    self(self, t + 1);
    for (int j = 0; j < n; ++j) {
      bool used = false;
      for (int k = 0; k < t; ++k) used |= l[k] == j;
      if (used) continue;
      if (!m.radius_fits(t, c[j].radius, p)) continue;
      l[t] = j;
      if (pair_ok(t)) self(self, t + 1);
      l[t] = -1;
    }
  };
  visit(visit, 0);
  if (best && model_metrics(c, *best, m, p).cost > p.model_max) return std::nullopt;
  return best;
}

Labelling assign_tracked(const std::vector<ModelCandidate>& c,
                         const std::array<std::optional<Eigen::Vector3d>, 4>& pred, const UdderModel& m,
                         const TrackerParams& p) {
  const int n = std::min<int>(static_cast<int>(c.size()), kMaxModelCandidates);
  const double miss = p.d_gate_mm + 0.5 * p.w_ncc;
  Labelling l{-1, -1, -1, -1}, best = l;
  double best_cost = std::numeric_limits<double>::infinity();
  const auto visit = [&](auto&& self, int t, double cost) -> void {
    if (cost >= best_cost) return;
    if (t == 4) {
      best_cost = cost;
      best = l;
      return;
    }
    l[t] = -1;
    self(self, t + 1, cost + (pred[t] ? miss : 0.0));
    if (!pred[t]) return;
    for (int j = 0; j < n; ++j) {
      bool used = false;
      for (int k = 0; k < t; ++k) used |= l[k] == j;
      if (used) continue;
      const double d = (c[j].tip - *pred[t]).norm();
      if (d > p.d_gate_mm) continue;
      if (!m.radius_fits(t, c[j].radius, p)) continue;
      l[t] = j;
      self(self, t + 1, cost + d + p.w_ncc * (1.0 - std::max(c[j].ncc, 0.0)));
      l[t] = -1;
    }
  };
  visit(visit, 0, 0.0);
  return best;
}

void learn(UdderModel& m, const std::vector<ModelCandidate>& c, const Labelling& l, double rate) {
  for (int i = 0; i < 6; ++i) {
    const auto [a, b] = kTeatPairs[i];
    if (l[a] < 0 || l[b] < 0) continue;
    const double d = (c[l[a]].tip - c[l[b]].tip).norm();
    m.dist[i] = std::isfinite(m.dist[i]) ? m.dist[i] + rate * (d - m.dist[i]) : d;
  }
  for (int t = 0; t < 4; ++t)
    if (l[t] >= 0)
      m.radius[t] = m.radius[t] > 0 ? m.radius[t] + rate * (c[l[t]].radius - m.radius[t]) : c[l[t]].radius;
}

}  // namespace trailscope::tracker::detail
