#include "tracker/detail/tip_fit.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Dense>

namespace trailscope::tracker::detail {
namespace {

using V3 = Eigen::Vector3d;

constexpr double kHuber = 2.5;        // mm: residuals beyond are down-weighted (flying pixels, udder)
constexpr double kPriorRadius = 0.7;  // mm: how strongly a tracked radius holds
constexpr double kPriorAxis = 0.3;    // rad
constexpr int kMinPoints = 8;
constexpr int kMaxWindowHalf = 48;  // px
constexpr double kMaxFitPoints = 110;
// Depth quantile of the seed pixel among those within the template's radius of the match (0 = nearest).
// 0.1 against 0 (the nearest pixel, trackers up to 1.3), 0.05 and 0.3 on tuning seeds 2000-2003: the share of
// frames within 10 mm rose on standard (0.943 to 0.958), fast-motion (0.777 to 0.807) and noisy (0.19 to
// 0.27); 0.3 puts the seed behind the tip's cap on small far tips (noisy's median error rose 1 mm).
constexpr double kSeedRank = 0.1;

struct Model {
  V3 c = V3::Zero(), a = V3::UnitZ();
  double r = 0;
};

// Signed distance of p from the capsule end: the hemisphere behind c (against a) and the cylinder ahead.
// Evaluated for every point at every step of every fit, so kept small enough to inline.
inline double residual(const Model& m, const V3& p) {
  const V3 q = p - m.c;
  const double t = q.dot(m.a);
  if (t <= 0) return std::max(q.norm(), 1e-9) - m.r;
  const V3 w = q - t * m.a;
  return std::max(w.norm(), 1e-9) - m.r;
}

// The residual and its derivatives J, the axis perturbed as a + x e1 + y e2 (e1, e2 orthonormal to a, the
// same for every point of an iteration, so computed once by the caller).
inline double residual(const Model& m, const V3& p, const V3& e1, const V3& e2,
                       Eigen::Matrix<double, 1, 6>& J) {
  const V3 q = p - m.c;
  const double t = q.dot(m.a);
  if (t <= 0) {
    const double d = std::max(q.norm(), 1e-9);
    J.segment<3>(0) = (-q / d).transpose();
    J.segment<2>(3).setZero();
    J(5) = -1;
    return d - m.r;
  }
  const V3 w = q - t * m.a;
  const double d = std::max(w.norm(), 1e-9);
  // d(d)/dx = -t (w . e1) / d.
  J.segment<3>(0) = (-w / d).transpose();
  J(3) = -t * w.dot(e1) / d;
  J(4) = -t * w.dot(e2) / d;
  J(5) = -1;
  return d - m.r;
}

struct Solve {
  Model m;
  double cost = 0;
  double rms = 0;
};

double robust_cost(const Model& m, const std::vector<V3>& pts, const TipPrior& prior, double* rms) {
  double c = 0, s2 = 0;
  for (const auto& p : pts) {
    const double r = residual(m, p), ar = std::fabs(r);
    c += ar <= kHuber ? 0.5 * r * r : kHuber * (ar - 0.5 * kHuber);
    const double cl = std::min(ar, 3 * kHuber);
    s2 += cl * cl;
  }
  if (prior.radius_mm > 0) c += 0.5 * std::pow((m.r - prior.radius_mm) / kPriorRadius, 2);
  const V3 pa(prior.axis[0], prior.axis[1], prior.axis[2]);
  if (pa.squaredNorm() > 0.5) c += 0.5 * (m.a - pa).squaredNorm() / (kPriorAxis * kPriorAxis);
  if (rms) *rms = std::sqrt(s2 / std::max<std::size_t>(pts.size(), 1));
  return c;
}

// Levenberg-Marquardt on the Huber loss (iteratively reweighted normal equations).
Solve refine(Model m, const std::vector<V3>& pts, const TipPrior& prior, int iterations) {
  double lambda = 1e-3;
  double cost = robust_cost(m, pts, prior, nullptr);
  const V3 pa(prior.axis[0], prior.axis[1], prior.axis[2]);
  for (int it = 0; it < iterations; ++it) {
    Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
    Eigen::Matrix<double, 1, 6> J;
    const V3 e1 = m.a.unitOrthogonal(), e2 = m.a.cross(e1);
    for (const auto& p : pts) {
      const double r = residual(m, p, e1, e2, J);
      const double w = std::fabs(r) <= kHuber ? 1.0 : kHuber / std::fabs(r);
      H.noalias() += w * J.transpose() * J;
      g.noalias() += w * r * J.transpose();
    }
    if (prior.radius_mm > 0) {
      const double s = 1.0 / (kPriorRadius * kPriorRadius);
      H(5, 5) += s;
      g(5) += s * (m.r - prior.radius_mm);
    }
    if (pa.squaredNorm() > 0.5) {
      const double s = 1.0 / (kPriorAxis * kPriorAxis);
      const V3 d = m.a - pa;
      H(3, 3) += s;
      H(4, 4) += s;
      g(3) += s * d.dot(e1);
      g(4) += s * d.dot(e2);
    }
    bool improved = false, converged = false;
    for (int tries = 0; tries < 6 && !improved; ++tries) {
      Eigen::Matrix<double, 6, 6> A = H;
      for (int i = 0; i < 6; ++i) A(i, i) += lambda * std::max(H(i, i), 1e-6);
      const Eigen::Matrix<double, 6, 1> dx = A.ldlt().solve(-g);
      if (!dx.allFinite()) break;
      Model n = m;
      n.c += dx.segment<3>(0);
      n.a = (m.a + dx(3) * e1 + dx(4) * e2).normalized();
      n.r = std::max(0.5, m.r + dx(5));
      const double nc = robust_cost(n, pts, prior, nullptr);
      if (nc < cost) {
        converged = cost - nc < 1e-5 * cost;
        m = n;
        cost = nc;
        lambda = std::max(lambda * 0.3, 1e-7);
        improved = true;
      } else {
        lambda *= 10;
      }
    }
    if (!improved || converged) break;
  }
  Solve s{m, 0, 0};
  s.cost = robust_cost(m, pts, prior, &s.rms);
  return s;
}

V3 backproject(const tof::Intrinsics& k, double u, double v, double z) {
  return {(u - k.cx) * z / k.fx, (v - k.cy) * z / k.fy, z};
}

// Points of the cloud within `reach` of `centre`, from a pixel window around its projection.
void gather(const PreparedFrame& f, const tof::Intrinsics& k, const V3& centre, double reach,
            std::vector<V3>& out) {
  out.clear();
  if (centre.z() <= 1) return;
  const double cu = k.fx * centre.x() / centre.z() + k.cx, cv = k.fy * centre.y() / centre.z() + k.cy;
  const int half = std::min(
      kMaxWindowHalf, static_cast<int>(std::ceil(k.fx * reach / std::max(centre.z() - reach, 10.0))) + 1);
  const int u0 = std::max(0, static_cast<int>(std::floor(cu)) - half),
            u1 = std::min(f.width - 1, static_cast<int>(std::ceil(cu)) + half);
  const int v0 = std::max(0, static_cast<int>(std::floor(cv)) - half),
            v1 = std::min(f.height - 1, static_cast<int>(std::ceil(cv)) + half);
  const double r2 = reach * reach;
  // Near the camera a tip covers hundreds of pixels; a regular subsample of about kMaxFitPoints keeps
  // the fit's cost flat without biasing it (the grid is uniform over the surface's image).
  const int stride =
      std::max(1, static_cast<int>(std::floor((2.0 * half + 1) / std::sqrt(kMaxFitPoints / 0.6))));
  for (int v = v0; v <= v1; v += stride)
    for (int u = u0; u <= u1; u += stride) {
      const float z = f.at(u, v);
      if (std::isnan(z)) continue;
      const V3 p = backproject(k, u, v, z);
      if ((p - centre).squaredNorm() <= r2) out.push_back(p);
    }
}

}  // namespace

TipFit fit_tip(const PreparedFrame& f, const tof::Intrinsics& k, double u, double v, double radius_px,
               const TrackerParams& p, const TipPrior& prior) {
  TipFit out;
  // Seed: a protruding pixel within the template's radius of the match. Not the nearest one: with a noisy
  // camera (sunlight, a dim far tip) the nearest of ~30 pixels is the deepest noise excursion towards the
  // camera, two noise sigmas in front of the surface, and the fit's reach is gathered around it. The pixel
  // at the kSeedRank quantile of depth is still on the tip (it faces the camera) and barely moved by noise.
  const int rr = std::max(1, static_cast<int>(std::ceil(radius_px)));
  std::vector<std::pair<float, int>> near;
  for (int y = std::max(0, static_cast<int>(v) - rr); y <= std::min(f.height - 1, static_cast<int>(v) + rr);
       ++y)
    for (int x = std::max(0, static_cast<int>(u) - rr); x <= std::min(f.width - 1, static_cast<int>(u) + rr);
         ++x) {
      const float z = f.at(x, y);
      if (!std::isnan(z)) near.push_back({z, y * f.width + x});
    }
  if (near.empty()) return out;
  const auto rank = near.begin() + static_cast<std::ptrdiff_t>(kSeedRank * double(near.size() - 1));
  std::nth_element(near.begin(), rank, near.end());
  const float bz = rank->first;
  const int bu = rank->second % f.width, bv = rank->second / f.width;
  const V3 p0 = backproject(k, bu, bv, bz);
  const V3 view = p0.normalized();
  const double r0 = prior.radius_mm > 0 ? prior.radius_mm : 0.5 * (p.r_min_mm + p.r_max_mm);

  std::vector<V3> pts;
  gather(f, k, p0, p.fit_reach_mm, pts);
  if (static_cast<int>(pts.size()) < kMinPoints) return out;

  // Candidate initial axes: the prior, the viewing ray (a teat seen end-on), and the cloud's main
  // direction (a teat seen from the side), each pointing away from the camera (tips face it).
  std::vector<V3> axes;
  const V3 pa(prior.axis[0], prior.axis[1], prior.axis[2]);
  if (pa.squaredNorm() > 0.5) axes.push_back(pa.normalized());
  if (axes.empty()) axes.push_back(view);
  if (axes.size() == 1 && pa.squaredNorm() <= 0.5) {
    V3 mean = V3::Zero();
    for (const auto& q : pts) mean += q;
    mean /= double(pts.size());
    Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
    for (const auto& q : pts) C += (q - mean) * (q - mean).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(C);
    V3 d = es.eigenvectors().col(2);
    if (d.dot(view) < 0) d = -d;
    axes.push_back(d);
  }
  Solve best;
  best.cost = INFINITY;
  for (const auto& a0 : axes) {
    Model m{p0 + r0 * a0, a0, r0};
    Solve s = refine(m, pts, prior, 10);
    if (s.cost < best.cost) best = s;
  }
  if (!std::isfinite(best.cost)) return out;
  // Re-centre the fit on the tip it found (the seed may sit on the teat's side) and refine once more.
  for (int pass = 0; pass < 1; ++pass) {
    const V3 apex = best.m.c - best.m.r * best.m.a;
    gather(f, k, apex, p.fit_reach_mm, pts);
    if (static_cast<int>(pts.size()) < kMinPoints) return out;
    best = refine(best.m, pts, prior, 6);
  }
  Model m = best.m;
  if (m.a.dot(m.c.normalized()) < 0) {
    // The fit flipped the axis to point at the camera: not a tip facing it.
    return out;
  }
  const V3 apex = m.c - m.r * m.a;
  out.ok = true;
  out.tip = {apex.x(), apex.y(), apex.z()};
  out.centre = {m.c.x(), m.c.y(), m.c.z()};
  out.axis = {m.a.x(), m.a.y(), m.a.z()};
  out.radius = m.r;
  out.rms = best.rms;
  out.points = static_cast<int>(pts.size());
  return out;
}

}  // namespace trailscope::tracker::detail
